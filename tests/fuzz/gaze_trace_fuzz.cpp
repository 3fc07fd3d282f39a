// Recorded gaze traces (t_ms,x,y or t_ms,x_norm,y_norm, or another tool's export through
// --gaze-trace-columns) replayed by fovview and fovstair.
#include <cmath>

#include "fuzz_input.h"
#include "gaze_log.h"
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
  // The same bytes as a gaze log (fovview --gaze-replay).
  fuzz::expect_clean(path, [&] {
    const std::vector<gaze_log_row> rows = read_gaze_log(path);
    fuzz::require(!rows.empty() && rows.back().frame + 1 == rows.size(), "a log's frames run 0, 1, 2, ...");
  });
  // The same bytes as another tool's export (--gaze-trace-columns): Pupil Player's columns,
  // and a mapping of the native header's names.
  for (const char* spec : {"pupil", "t_ms,x,y;coords=norm-bottom-left;time=us"}) {
    trace_columns columns;
    fuzz::require(parse_trace_columns(spec, columns).empty(), "the specs parse");
    fuzz::expect_clean(path, [&] {
      const auto source = table_gaze(path, columns, 64, 48);
      for (double t : {-1.0, 0.0, 16.7, 1e3, 1e9}) {
        const gaze_point g = source->poll(t);
        fuzz::require(g.x >= 0 && g.x <= 64 && g.y >= 0 && g.y <= 48, "the gaze lies on the screen");
      }
    });
  }
  return 0;
}
