// A Pupil Labs gaze or surface message as --gaze-pupil receives it: the topic frame, a NUL, then the
// msgpack payload frame (parse_pupil_gaze). It must refuse with one short line and allocate
// within a small multiple of the payload (msgpack-c allocates what a container declares).
#include <cmath>
#include <cstring>

#include "fuzz_input.h"
#include "pupil_gaze.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const void* nul = std::memchr(data, 0, size);
  const size_t topic_size = nul ? size_t(static_cast<const uint8_t*>(nul) - data) : size;
  const std::string topic(reinterpret_cast<const char*>(data), topic_size);
  const unsigned char* payload = data + std::min(size, topic_size + 1);
  const size_t payload_size = size - std::min(size, topic_size + 1);
  std::vector<fov::pupil_gaze_message> decoded;
  try {
    const std::string why = fov::parse_pupil_gaze(topic, payload, payload_size, decoded);
    if (why.empty())
      for (const fov::pupil_gaze_message& m : decoded)
        fov::fuzz::require(std::isfinite(m.norm_x) && std::isfinite(m.norm_y) && std::isfinite(m.timestamp) &&
                               m.confidence >= 0 && m.confidence <= 1,
                           "an accepted message is finite with a confidence in 0..1");
    else
      fov::fuzz::require(why.size() < 200 && why.find('\n') == std::string::npos, "a refusal is one short line");
  } catch (const std::exception& e) {
    fov::fuzz::finding("a message threw (it must be counted as malformed)", e.what());
  }
  return 0;
}
