// Checks on the files a tool reads before it opens or allocates for them, and the one way
// every tool writes a file: a temporary file beside it, renamed into place when complete.
#pragma once

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace fov {

// Any problem with a file: the message names the file and the reason.
class file_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Why `path` cannot be read as an input file, or "" when it can: it does not exist, is a
// directory, or is not a regular file (a FIFO, device or socket, whose open or read may
// block or never end), or, with `max_bytes`, holds more bytes than that ("N bytes; a
// `what` may hold at most MAX"). Symbolic links are followed.
std::string input_file_problem(const std::string& path, uintmax_t max_bytes = 0, const std::string& what = "file");

// The same check on a file already open (descriptor `fd`): what input_file_problem says of
// the file it is, or "cannot read: ..." when it cannot be examined.
std::string open_file_problem(int fd, uintmax_t max_bytes = 0, const std::string& what = "file");

// Reads the whole of an input file: refused as input_file_problem(path, max_bytes, what)
// says (with max_bytes 0, the machine's memory bounds it), checked on the
// descriptor it reads, which is opened without blocking, so a FIFO or device put in the
// file's place after a check is refused too. Throws file_error "PATH: reason".
std::string read_input_file(const std::string& path, uintmax_t max_bytes, const std::string& what = "file");

// The machine's physical memory in bytes (0 when unknown): what no single allocation a
// file asks for may exceed.
uint64_t physical_memory_bytes();

// "" when `bytes` (what `what` needs) fits in physical memory, else why not, in one line.
std::string memory_problem(uint64_t bytes, const std::string& what);

// Text from an input, fit to quote in a one-line message: control characters and bytes
// outside printable ASCII written as \n, \t or \xNN, and the result at most `max_chars`
// long (then "..."), however many bytes each input character became.
std::string printable(const std::string& text, size_t max_chars = 60);

// The first line of a library's message (OpenImageIO's may run to several, with debug lines).
std::string first_line(const std::string& message);

// While one exists, this process's stderr goes nowhere: around a library call that prints
// its own lines for an error it also returns (libpng writes "libpng error: ..." to stderr
// before OpenImageIO reports the same), so the tool prints one line. Only for short calls
// made before a tool's work starts (reading its input images): other threads' messages
// would be lost with it.
class stderr_silenced {
 public:
  stderr_silenced();
  ~stderr_silenced();
  stderr_silenced(const stderr_silenced&) = delete;
  stderr_silenced& operator=(const stderr_silenced&) = delete;

 private:
  int saved_ = -1;
};

// Why `path` cannot be an output, or "" when it can: it is a directory; a symbolic link
// (refused, not written through: outputs are replaced by renaming a finished temporary file
// onto them, which would replace the link); an existing file that is not regular (a device,
// FIFO or socket, which the rename would replace); or the same file as one of `inputs`
// (the command would overwrite what it reads). A missing file is fine.
std::string output_file_problem(const std::string& path, const std::vector<std::string>& inputs = {});

// True when both paths name one existing file (through links too).
bool same_file(const std::string& a, const std::string& b);

// A file being written: a temporary file beside `path`, PATH.tmp-PID-XXXXXX plus `suffix`
// (an extension, for writers that choose the format by name), that commit() renames onto
// `path`; destroyed uncommitted (an error), it is removed, so `path` is never half written.
// SIGINT and SIGTERM remove every temporary file still open before the process ends; the
// temporary files of `path` that a killed process left (kill -9, a crash) are removed when
// the next one is made, each with a note on stderr. Throws file_error naming `path`, when
// output_file_problem(path) is not empty too.
class temp_output {
 public:
  explicit temp_output(const std::string& path, const std::string& suffix = "");
  ~temp_output();
  temp_output(const temp_output&) = delete;
  temp_output& operator=(const temp_output&) = delete;

  const std::string& temp_path() const { return tmp_; }  // for writers that open files by name
  void write_at(uint64_t offset, const void* data, size_t bytes);
  void commit();  // flush, fsync and rename into place

 private:
  std::string path_, tmp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
  int slot_ = -1;  // in the signal handler's list
};

// Makes the directory `dir` and its missing parents; file_error "DIR: reason" in one line
// (a part of the path that is a file, a directory it cannot write in) instead of the
// filesystem library's text.
void make_output_dir(const std::string& dir);

// Writes bytes to `path` through a temp_output.
void write_file_atomic(const std::string& path, const void* data, size_t bytes);

// Fails early with file_error when `path` cannot be written: output_file_problem, or its
// directory is missing or not writable (a temporary file is made and removed).
void check_writable(const std::string& path, const std::vector<std::string>& inputs = {});

}  // namespace fov
