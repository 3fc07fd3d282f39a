// Recorded gaze traces (t_ms,x,y or t_ms,x_norm,y_norm) replayed by fovview and fovstair.
#include <cmath>

#include "fuzz_input.h"
#include "gaze_source.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "gaze.csv");
  fuzz::expect_clean(path, [&] {
    const auto source = trace_gaze(path, 64, 48);
    for (double t : {-1.0, 0.0, 16.7, 1e3, 1e9}) {
      const gaze_point g = source->poll(t);
      fuzz::require(g.x >= 0 && g.x <= 64 && g.y >= 0 && g.y <= 48, "the gaze lies on the screen");
    }
  });
  return 0;
}
