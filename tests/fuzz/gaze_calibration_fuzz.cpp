// Gaze calibration files (--gaze-calibration): offset/scale, a homography or a validation grid.
#include <cmath>

#include "fuzz_input.h"
#include "gaze_source.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "calibration.json");
  fuzz::expect_clean(path, [&] {
    const gaze_calibration c = read_gaze_calibration(path);
    double x = 0.5, y = 0.5;
    fuzz::require(c.apply(x, y) && std::isfinite(x) && std::isfinite(y), "an accepted calibration maps the centre");
  });
  return 0;
}
