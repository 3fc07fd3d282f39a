#include "line_log.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

namespace fov {

namespace {

[[noreturn]] void fail_io(const std::string& path, const char* what) {
  throw std::runtime_error(fmt::format("{}: {}: {}", path, what, std::strerror(errno)));
}

}  // namespace

line_log::line_log(const std::string& path, mode m) : path_(path) {
  const int flags = O_WRONLY | O_APPEND | O_CLOEXEC | (m == mode::open_existing ? 0 : O_CREAT) |
                    (m == mode::create_new ? O_EXCL : 0);
  fd_ = ::open(path.c_str(), flags, 0644);
  if (fd_ < 0) {
    if (errno == EEXIST) throw file_exists_error(fmt::format("{}: exists", path));
    fail_io(path, m == mode::open_existing ? "cannot open for appending" : "cannot create");
  }
  if (m == mode::create_new) {  // the new name must survive a crash too: sync the directory entry
    const std::string dir = path.find('/') == std::string::npos ? "." : path.substr(0, path.rfind('/') + 1);
    if (const int d = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); d >= 0) ::fsync(d), ::close(d);
    return;
  }
  // Keep complete lines only: cut a torn last line.
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t keep = text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1;
  if (keep < text.size() && ::ftruncate(fd_, off_t(keep)) != 0) {
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
