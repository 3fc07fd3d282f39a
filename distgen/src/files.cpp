#include "fov/files.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace fov {

std::string input_file_problem(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return fmt::format("cannot open: {}", std::strerror(errno));
  if (S_ISDIR(st.st_mode)) return "is a directory, not a file";
  if (!S_ISREG(st.st_mode)) return "not a regular file (a FIFO, device or socket): refused";
  return "";
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

}  // namespace fov
