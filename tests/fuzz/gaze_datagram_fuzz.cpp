// The UDP gaze datagram "x y" (normalised), as fovview and fovstair read it from the socket.
#include <cmath>

#include "fuzz_input.h"
#include "gaze_source.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  double x = -1, y = -1;
  try {
    if (fov::parse_gaze_datagram(text, x, y)) fov::fuzz::require(std::isfinite(x) && std::isfinite(y), "a gaze is finite");
  } catch (const std::exception& e) {
    fov::fuzz::finding("a datagram threw (it must be counted as malformed)", e.what());
  }
  return 0;
}
