// The UDP gaze datagram ("X Y" or "v2 T C EYE X Y"), as fovview and fovstair read it from the socket.
#include <cmath>

#include "fuzz_input.h"
#include "gaze_source.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fov::gaze_datagram d;
  try {
    const std::string why = fov::parse_gaze_datagram(text, d);
    if (why.empty())
      fov::fuzz::require(std::isfinite(d.x) && std::isfinite(d.y) && d.confidence >= 0 && d.confidence <= 1,
                         "an accepted datagram is finite with a confidence in 0..1");
    else
      fov::fuzz::require(why.size() < 200, "a refusal is one short line");
  } catch (const std::exception& e) {
    fov::fuzz::finding("a datagram threw (it must be counted as malformed)", e.what());
  }
  return 0;
}
