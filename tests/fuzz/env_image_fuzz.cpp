// env: images (lat-long environment maps) through OpenImageIO: the first byte picks the
// format (Radiance HDR, OpenEXR, PNG), the rest is the file.
#include "fov/scene.h"
#include "fuzz_input.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* names[] = {"env.hdr", "env.exr", "env.png"};
  const std::string path = fuzz::write_input(data + 1, size - 1, names[data[0] % 3]);
  fuzz::expect_clean(path, [&] {  // messages name the image, not the env: spec
    const std::unique_ptr<scene> s = load_scene("env:" + path);
    for (const std::string& w : s->warnings()) fuzz::require(w.find('\n') == std::string::npos, "warnings are one line");
  });
  return 0;
}
