// Recorded camera paths (t_ms,x,y,z,tx,ty,tz) replayed by fovview and fovrender.
#include <cmath>

#include "camera_path.h"
#include "fuzz_input.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "camera.csv");
  fuzz::expect_clean(path, [&] {
    const camera_path cp = load_camera_path(path);
    fuzz::require(!cp.keys.empty(), "a path has keys");
    const camera base;
    for (double t : {-1.0, 0.0, 0.5, 16.7, 1e3, 1e12}) {
      const camera c = cp.at(t, base);
      fuzz::require(std::isfinite(c.position.x) && std::isfinite(c.position.y) && std::isfinite(c.position.z) &&
                        std::isfinite(c.forward.x) && std::isfinite(c.forward.y) && std::isfinite(c.forward.z),
                    "the camera is finite");
    }
  });
  return 0;
}
