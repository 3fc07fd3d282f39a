// An append-only file of lines that survives crashes (fovstair sessions, fovbench results):
// every line is written whole and fsync'ed before append_line returns, and opening an
// existing file cuts a torn last line (no newline) that an interrupted write left.
#pragma once

#include <stdexcept>
#include <string>

namespace fov {

// Thrown by line_log(path, create_new) when the file exists.
struct file_exists_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class line_log {
 public:
  enum class mode {
    create_new,      // the file must not exist (its directory entry is fsync'ed too)
    open_existing,   // the file must exist
    create_or_open,  // either
  };
  // Throws std::runtime_error "PATH: reason" (file_exists_error for create_new).
  line_log(const std::string& path, mode m);
  ~line_log();
  line_log(line_log&& o) noexcept : fd_(o.fd_), empty_(o.empty_), path_(std::move(o.path_)) { o.fd_ = -1; }
  line_log(const line_log&) = delete;
  line_log& operator=(const line_log&) = delete;

  bool empty() const { return empty_; }  // no complete line yet
  void append_line(const std::string& text);  // adds the newline

 private:
  int fd_ = -1;
  bool empty_ = true;
  std::string path_;
};

}  // namespace fov
