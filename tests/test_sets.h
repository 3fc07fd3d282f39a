// Small point sets for tests.
#pragma once

#include "fov/dart_throwing.h"
#include "fov/knn_cells.h"
#include "fov/knn_table.h"

namespace fov::testing {

inline spacing_model small_model(int w, int h, double v = 1.0, double s = 1.0) {
  spacing_model m;
  m.display = {w, h, v};
  m.scale = s;
  return m;
}

inline dart_params quick_darts(uint64_t seed = 7, uint32_t saturation = 2000) {
  dart_params d;
  d.seed = seed;
  d.saturation_rejections = saturation;
  d.free_area_probes = 1u << 16;
  return d;
}

// A small screen seen from far away (N v = 1280, as a FOVE's 1280 px at v = 1) and thinned
// by s = 4, so that its foveal grid covers a disc of about 52 px radius and darts the rest.
inline spacing_model partial_grid_model() { return small_model(128, 96, 10.0, 4.0); }
inline dart_params grid_darts(uint64_t seed = 7) {
  dart_params d = quick_darts(seed);
  d.fovea = fovea_layout::grid;
  return d;
}

// One set kept both ways: with its exact table and (a copy) with k-NN cells of the same k.
struct table_and_cells {
  pointset table, cells;
};
inline table_and_cells both_ways(const spacing_model& m, const dart_params& d, uint32_t k) {
  table_and_cells out;
  knn_params kp;
  kp.k = k;
  out.table = generate_pointset(m, d, kp);
  out.cells = out.table;
  build_neighbours(out.cells, kp, knn_storage::cells);
  return out;
}

// Pairs closer than min(p_i, p_j), by checking every pair.
inline uint64_t brute_force_violations(const std::vector<point>& pts) {
  uint64_t n = 0;
  for (size_t i = 0; i < pts.size(); ++i)
    for (size_t j = i + 1; j < pts.size(); ++j) {
      const double dx = double(pts[i].x) - pts[j].x, dy = double(pts[i].y) - pts[j].y;
      const double m = std::min(pts[i].spacing, pts[j].spacing);
      if (dx * dx + dy * dy < m * m) ++n;
    }
  return n;
}

}  // namespace fov::testing
