#include "fov/files.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>

#include <fmt/format.h>

namespace fov {

namespace {

std::string stat_problem(const struct stat& st, uintmax_t max_bytes, const std::string& what) {
  if (S_ISDIR(st.st_mode)) return "is a directory, not a file";
  if (!S_ISREG(st.st_mode)) return "not a regular file (a FIFO, device or socket): refused";
  if (max_bytes > 0 && uintmax_t(st.st_size) > max_bytes)
    return fmt::format("{} bytes; a {} may hold at most {}", uintmax_t(st.st_size), what, max_bytes);
  return "";
}

}  // namespace

std::string input_file_problem(const std::string& path, uintmax_t max_bytes, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return fmt::format("cannot open: {}", std::strerror(errno));
  return stat_problem(st, max_bytes, what);
}

std::string open_file_problem(int fd, uintmax_t max_bytes, const std::string& what) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return fmt::format("cannot read: {}", std::strerror(errno));
  return stat_problem(st, max_bytes, what);
}

std::string read_input_file(const std::string& path, uintmax_t max_bytes, const std::string& what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw file_error(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  struct stat st {};
  std::string why = ::fstat(fd, &st) != 0 ? fmt::format("cannot read: {}", std::strerror(errno))
                                          : stat_problem(st, max_bytes > 0 ? max_bytes : physical_memory_bytes(), what);
  std::string text;
  if (why.empty()) {
    text.resize(size_t(st.st_size));
    size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = ::read(fd, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) why = fmt::format("cannot read: {}", std::strerror(errno));
      if (n <= 0) break;  // shorter than it was: what was there
      done += size_t(n);
    }
    text.resize(done);
  }
  ::close(fd);
  if (!why.empty()) throw file_error(fmt::format("{}: {}", path, why));
  return text;
}

uint64_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : 0;
}

std::string memory_problem(uint64_t bytes, const std::string& what) {
  const uint64_t memory = physical_memory_bytes();
  if (memory == 0 || bytes <= memory) return "";
  return fmt::format("{} needs {:.1f} GB, more than this machine's {:.1f} GB of memory", what, double(bytes) / 1e9,
                     double(memory) / 1e9);
}

std::string first_line(const std::string& message) {
  const size_t end = message.find('\n');
  return end == std::string::npos ? message : message.substr(0, end);
}

stderr_silenced::stderr_silenced() {
  std::fflush(stderr);
  saved_ = ::dup(2);
  const int null = ::open("/dev/null", O_WRONLY);
  if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
  if (null >= 0) ::close(null);
}

stderr_silenced::~stderr_silenced() {
  if (saved_ < 0) return;
  std::fflush(stderr);
  ::dup2(saved_, 2);
  ::close(saved_);
}

std::string printable(const std::string& text, size_t max_chars) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    std::string piece;
    if (c == '\n') piece = "\\n";
    else if (c == '\t') piece = "\\t";
    else if (c < 0x20 || c >= 0x7f) piece = fmt::format("\\x{:02x}", c);
    else piece = char(c);
    if (out.size() + piece.size() > max_chars) return out + "...";
    out += piece;
  }
  return out;
}

std::string output_file_problem(const std::string& path, const std::vector<std::string>& inputs) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) return "a symbolic link: give the file it points to (outputs are replaced, never written through)";
    if (S_ISDIR(st.st_mode)) return "is a directory, not a file";
    if (!S_ISREG(st.st_mode)) return "exists and is not a regular file (a device, FIFO or socket): refused";
  }
  for (const std::string& in : inputs)
    if (!in.empty() && same_file(path, in)) return fmt::format("is also an input ({}): refused, it would be overwritten", in);
  return "";
}

void make_output_dir(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path at;
  for (const fs::path& part : fs::path(dir)) {
    at /= part;
    if (part.empty() || part == "/") continue;
    const fs::file_status st = fs::status(at, ec);
    if (fs::is_directory(st)) continue;
    if (fs::exists(st)) throw file_error(fmt::format("{}: cannot make the directory: {} is not a directory", dir, at.string()));
    if (!fs::create_directory(at, ec) && !fs::is_directory(at))
      throw file_error(fmt::format("{}: cannot make the directory {}: {}", dir, at.string(), ec.message()));
  }
}

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

namespace {

// The temporary files open in this process, for the SIGINT/SIGTERM handler: signals are
// process-wide, so this list is the one piece of process-wide state (slots hold strings
// allocated before they are published; the handler only reads them and calls unlink).
constexpr int temp_slots = 64;
std::atomic<char*> open_temps[temp_slots];

void remove_temps_and_reraise(int sig) {
  for (auto& slot : open_temps)
    if (char* p = slot.load()) ::unlink(p);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

int register_temp(const std::string& path) {
  static std::once_flag installed;
  std::call_once(installed, [] {
    for (int sig : {SIGINT, SIGTERM}) {
      struct sigaction old {};
      // Only where nobody else handles the signal: a tool's own handler stays in charge.
      if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_DFL) std::signal(sig, remove_temps_and_reraise);
    }
  });
  char* copy = ::strdup(path.c_str());
  for (int i = 0; i < temp_slots; ++i) {
    char* expected = nullptr;
    if (open_temps[i].compare_exchange_strong(expected, copy)) return i;
  }
  std::free(copy);  // more open at once than slots: this one is only removed by the next run
  return -1;
}

void unregister_temp(int slot) {
  if (slot < 0) return;
  std::free(open_temps[slot].exchange(nullptr));
}

// Removes PATH.tmp-PID-* whose process no longer runs (kill(PID, 0) fails with ESRCH).
void remove_stale_temps(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
  const std::string prefix = p.filename().string() + ".tmp-";
  DIR* d = ::opendir(dir.c_str());
  if (!d) return;
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    char* end = nullptr;
    const long pid = std::strtol(name.c_str() + prefix.size(), &end, 10);
    if (pid <= 0 || *end != '-' || pid == long(::getpid())) continue;
    if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to know
    const std::string stale = (fs::path(dir) / name).string();
    if (::unlink(stale.c_str()) == 0)
      std::cerr << fmt::format("note: removed {}, a temporary file left by process {}, which no longer runs\n", stale, pid);
  }
  ::closedir(d);
}

}  // namespace

temp_output::temp_output(const std::string& path, const std::string& suffix) : path_(path) {
  if (const std::string why = output_file_problem(path); !why.empty()) throw file_error(fmt::format("{}: {}", path, why));
  remove_stale_temps(path);
  tmp_ = fmt::format("{}.tmp-{}-XXXXXX{}", path, ::getpid(), suffix);
  const int fd = ::mkstemps(tmp_.data(), int(suffix.size()));
  if (fd < 0) throw file_error(fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
  slot_ = register_temp(tmp_);
  file_ = ::fdopen(fd, "wb");
  if (!file_) {
    ::close(fd);
    ::unlink(tmp_.c_str());
    unregister_temp(slot_);
    throw file_error(fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
  }
}

temp_output::~temp_output() {
  if (file_) std::fclose(file_);
  if (!committed_) ::unlink(tmp_.c_str());
  unregister_temp(slot_);
}

void temp_output::write_at(uint64_t offset, const void* data, size_t bytes) {
  if (!file_ || ::fseeko(file_, off_t(offset), SEEK_SET) != 0 || std::fwrite(data, 1, bytes, file_) != bytes)
    throw file_error(fmt::format("{}: write failed: {}", path_, std::strerror(errno)));
}

void temp_output::commit() {
  if (file_) {
    const bool ok = std::fflush(file_) == 0 && ::fsync(fileno(file_)) == 0;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed) throw file_error(fmt::format("{}: write failed: {}", path_, std::strerror(errno)));
  }
  // A writer that opened temp_path() by name has closed it; the file must be there, whole.
  ::chmod(tmp_.c_str(), 0644);
  // Checked again: the output may have become a link or a device since the temp was made.
  if (const std::string why = output_file_problem(path_); !why.empty()) throw file_error(fmt::format("{}: {}", path_, why));
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw file_error(fmt::format("{}: cannot rename into place: {}", path_, std::strerror(errno)));
  committed_ = true;
}

void write_file_atomic(const std::string& path, const void* data, size_t bytes) {
  temp_output out(path);
  out.write_at(0, data, bytes);
  out.commit();
}

void check_writable(const std::string& path, const std::vector<std::string>& inputs) {
  if (const std::string why = output_file_problem(path, inputs); !why.empty()) throw file_error(fmt::format("{}: {}", path, why));
  temp_output probe(path);  // creates and removes a temporary file beside path
}

}  // namespace fov
