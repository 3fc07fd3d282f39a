#include "line_log.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "fov/files.h"

namespace fov {

namespace {

[[noreturn]] void fail_io(const std::string& path, const char* what) {
  throw std::runtime_error(fmt::format("{}: {}: {}", path, what, std::strerror(errno)));
}

}  // namespace

line_log::line_log(const std::string& path, mode m) : path_(path) {
  // O_NOFOLLOW: an append is refused through a symbolic link, as every write is (it would
  // change the link's target); O_NONBLOCK: a FIFO without a reader is refused, not waited on.
  const int flags = O_RDWR | O_APPEND | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK |
                    (m == mode::open_existing ? 0 : O_CREAT) | (m == mode::create_new ? O_EXCL : 0);
  fd_ = ::open(path.c_str(), flags, 0644);
  if (fd_ < 0) {
    if (errno == EEXIST) throw file_exists_error(fmt::format("{}: exists", path));
    if (errno == ELOOP)
      throw std::runtime_error(fmt::format("{}: a symbolic link: give the file it points to (appends are refused through links)", path));
    fail_io(path, m == mode::open_existing ? "cannot open for appending" : "cannot create");
  }
  if (const std::string why = open_file_problem(fd_); !why.empty()) {  // a FIFO, device or socket
    ::close(fd_);
    throw std::runtime_error(fmt::format("{}: {}", path, why));
  }
  if (m == mode::create_new) {  // the new name must survive a crash too: sync the directory entry
    const std::string dir = path.find('/') == std::string::npos ? "." : path.substr(0, path.rfind('/') + 1);
    if (const int d = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); d >= 0) ::fsync(d), ::close(d);
    return;
  }
  // Keep complete lines only: cut a torn last line (after the last newline).
  size_t keep = 0;
  char buffer[4096];
  const off_t size = ::lseek(fd_, 0, SEEK_END);
  for (off_t end = size; end > 0 && keep == 0;) {
    const size_t n = size_t(std::min<off_t>(end, off_t(sizeof buffer)));
    end -= off_t(n);
    if (::pread(fd_, buffer, n, end) != ssize_t(n)) {
      ::close(fd_);
      fail_io(path, "cannot read");
    }
    for (size_t i = n; i-- > 0;)
      if (buffer[i] == '\n') {
        keep = size_t(end) + i + 1;
        break;
      }
  }
  if (off_t(keep) < size && ::ftruncate(fd_, off_t(keep)) != 0) {
    ::close(fd_);
    fail_io(path, "cannot cut the torn last line");
  }
  empty_ = keep == 0;
}

line_log::~line_log() {
  if (fd_ >= 0) ::close(fd_);
}

void line_log::append_line(const std::string& text) {
  const std::string line = text + "\n";
  for (size_t done = 0; done < line.size();) {
    const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail_io(path_, "cannot write");
    done += size_t(n);
  }
  if (::fsync(fd_) != 0) fail_io(path_, "cannot fsync");
  empty_ = false;
}

}  // namespace fov
