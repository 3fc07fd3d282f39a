#include "fuzz_input.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>

namespace fov::fuzz {

namespace fs = std::filesystem;

namespace {

struct scratch {
  std::string dir;
  scratch() {
    const char* tmp = std::getenv("TMPDIR");
    dir = (fs::path(tmp && *tmp ? tmp : "/tmp") / ("fovfuzz-" + std::to_string(::getpid()))).string();
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

}  // namespace

const std::string& scratch_dir() {
  static const scratch s;  // one per process: the fuzzer's, or the replay's
  return s.dir;
}

std::string write_input(const uint8_t* data, size_t size, const std::string& name) {
  const std::string path = (fs::path(scratch_dir()) / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) finding("cannot write the scratch input", path.c_str());
  return path;
}

}  // namespace fov::fuzz
