// The .fovset reader: header, sections, table decoding (raw and ref-left-zstd). Fuzz
// builds skip checksum comparison (FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION), so mutations
// reach the checks behind them. A set the reader accepts must hold what the renderer
// relies on without checking: points on the canvas, table indices in range, and the
// traced-point index finding the same points as the table scan.
#include "fov/pointset.h"
#include "fov/pointset_io.h"
#include "fuzz_input.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "input.fovset");
  fuzz::expect_clean(path, [&] {
    load_params header_only;
    header_only.table = false;
    const pointset shape = load_pointset(path, header_only);
    fuzz::require(shape.table.entries.empty() && shape.table.width == shape.canvas_width(), "header-only load");
    const pointset set = load_pointset(path);
    const knn_table& t = set.table;
    fuzz::require(t.width == set.canvas_width() && t.height == set.canvas_height(), "table covers the canvas");
    fuzz::require(t.entries.size() == t.pixel_count() * t.k, "table size");
    for (uint32_t v : t.entries) fuzz::require(v < set.points.size(), "table index in range");
    for (const point& p : set.points)
      fuzz::require(p.x >= 0 && p.x < float(t.width) && p.y >= 0 && p.y < float(t.height), "point on the canvas");
    const display_geometry& d = set.model.display;
    const traced_index index = make_traced_index(set, t.k);
    for (const gaze_point g : {gaze_point{d.width / 2.0, d.height / 2.0}, gaze_point{0, 0}, gaze_point{double(d.width), 0}})
      fuzz::require(traced_points(set, index, g) == traced_points(set, g, t.k), "index and scan agree");
  });
  return 0;
}
