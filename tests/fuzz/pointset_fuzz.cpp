// The .fovset reader: header, sections, table decoding (raw and ref-left-zstd), cells built
// from the points (cells), a nested set's levels (version 3). Fuzz
// builds skip checksum comparison (FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION), so mutations
// reach the checks behind them. A set the reader accepts must hold what the renderer
// relies on without checking: points on the canvas, table indices in range, and the
// traced-point index finding the same points as the table scan.
#include <memory>

#include "fov/knn_cells.h"
#include "fov/knn_table.h"
#include "fov/nested.h"
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
    fuzz::require(shape.table.entries.empty() && shape.cells.candidates.empty(), "header-only load");
    fuzz::require(stored_k(shape) > 0, "header-only load keeps k");
    const pointset set = load_pointset(path);
    const uint32_t w = set.canvas_width(), h = set.canvas_height(), k = stored_k(set);
    if (set.storage() == knn_storage::table) {
      const knn_table& t = set.table;
      fuzz::require(t.width == w && t.height == h, "table covers the canvas");
      fuzz::require(t.entries.size() == t.pixel_count() * t.k, "table size");
      for (uint32_t v : t.entries) fuzz::require(v < set.points.size(), "table index in range");
    } else {  // cells: built by the loader from the points, so exact; every pixel's neighbours in range
      fuzz::require(knn_cells_problem(set.cells, set.points.size()).empty(), "cells consistent");
      uint32_t found[max_knn];
      for (uint32_t y = 0; y < h; y += 7)
        for (uint32_t x = 0; x < w; x += 7) {
          pixel_neighbours(set, x, y, k, found);
          for (uint32_t j = 0; j < k; ++j) fuzz::require(found[j] < set.points.size(), "cell neighbour in range");
        }
    }
    if (set.nested()) {  // every level a set the renderer can read: its cells consistent, its points the set's
      const nested_levels levels = make_levels(std::make_shared<const pointset>(set));
      fuzz::require(levels.levels.size() == set.level_count(), "a set per level");
      for (const set_level& l : levels.levels) {
        if (l.set->cells.loaded())
          fuzz::require(knn_cells_problem(l.set->cells, l.set->points.size()).empty(), "level cells consistent");
        for (uint32_t i : l.global) fuzz::require(i < set.points.size(), "level point in range");
      }
    }
    for (const point& p : set.points)
      fuzz::require(p.x >= 0 && p.x < float(w) && p.y >= 0 && p.y < float(h), "point on the canvas");
    const display_geometry& d = set.model.display;
    const traced_index index = make_traced_index(set, k);
    for (const gaze_point g : {gaze_point{d.width / 2.0, d.height / 2.0}, gaze_point{0, 0}, gaze_point{double(d.width), 0}})
      fuzz::require(traced_points(set, index, g) == traced_points(set, g, k), "index and scan agree");
  });
  return 0;
}
