// Exact k-nearest-neighbour tables for every canvas pixel of a point set.
#pragma once

#include <memory>
#include <vector>

#include "fov/pointset.h"

namespace fov {

// The largest k a table may store.
inline constexpr uint32_t max_knn = 32;

struct knn_params {
  uint32_t k = 20;     // neighbours stored per pixel, 1..max_knn
  uint32_t group = 4;  // ranks per plane group (see knn_table); clamped to 1..k
};

// Answers "the k nearest points of each pixel centre in these rows", exactly.
// FLANN's single kd-tree searches in float, so it is asked for a few extra
// neighbours that are re-ranked by distance in double (ties: smaller index
// first): results are exact and independent of thread count.
class knn_builder {
 public:
  knn_builder(const std::vector<point>& points, uint32_t canvas_width, uint32_t canvas_height, uint32_t k);
  ~knn_builder();
  // Writes rows [y0, y1) pixel-major: out[((y - y0) * width + x) * k + rank]. Parallel.
  void rows(uint32_t y0, uint32_t y1, uint32_t* out) const;
  uint32_t k() const { return k_; }

 private:
  struct impl;
  std::unique_ptr<impl> impl_;
  const std::vector<point>& points_;
  uint32_t width_, height_, k_;
};

// Bytes of the table of a set for this display: (2W)(2H) k point indices.
inline uint64_t knn_table_bytes(const display_geometry& display, uint32_t k) {
  return 4ull * uint64_t(display.width) * uint64_t(display.height) * k * sizeof(uint32_t);
}

// "" when that table fits in this machine's memory, else why not (fov::memory_problem).
std::string knn_table_memory_problem(const display_geometry& display, uint32_t k);

// Builds the whole table in memory.
knn_table build_knn_table(const std::vector<point>& points, uint32_t canvas_width,
                          uint32_t canvas_height, const knn_params& params);

// The same ranking by brute force over all points: slow, for tests.
std::vector<uint32_t> brute_force_knn(const std::vector<point>& points, float qx, float qy, uint32_t k);

// Copies a table into another group size (same entries, other layout).
knn_table regroup(const knn_table& table, uint32_t group);

// Builds the set's neighbours the way asked for, the table (knn: k and group) or the cells
// (knn_cells.h, with knn.k), and drops the other kind if it held one.
void build_neighbours(pointset& set, const knn_params& knn, knn_storage storage);

// The set's points as darts.sampler places them: throw_darts for poisson, lattice_points
// (lattice.h) for a ring lattice (stats then only its seconds; a grid fovea is refused).
std::vector<point> place_points(const spacing_model& model, const dart_params& darts, dart_stats* stats);

// Places the points (place_points) and builds the table (or the cells) in memory.
pointset generate_pointset(const spacing_model& model, const dart_params& darts, const knn_params& knn,
                           knn_storage storage = knn_storage::table);

// A nested set (fovgen --levels; dart_throwing.h) without neighbours: its levels thrown at
// these scales (increasing, finest first: levels_problem; std::invalid_argument otherwise),
// level_scales coarsest first, its model at the finest scale.
pointset throw_nested_pointset(const spacing_model& model, const std::vector<double>& scales, const dart_params& darts);
// The number of points of a nested set's coarsest level (all points of a fixed set).
uint64_t coarsest_level_points(const pointset& set);

// throw_nested_pointset with its neighbours built; std::invalid_argument also when knn.k
// exceeds the coarsest level's points.
pointset generate_nested_pointset(const spacing_model& model, const std::vector<double>& scales, const dart_params& darts,
                                  const knn_params& knn, knn_storage storage = knn_storage::table);

// The non-foveated baseline: a set of uniform density `fraction` of the display's pixels
// (1/2, 1/4, 1/8, ...: 1 / 2^m), built and traced like a foveated one. For fraction 4^-j
// the points are the centres of the 2^j x 2^j pixel blocks (a lower-resolution image's
// pixels); for 2 x 4^-j, every other block centre in a checkerboard (a quincunx), spacing
// sqrt(2) 2^j. Each point's spacing is its nearest neighbour's distance. Throws
// std::invalid_argument for any other fraction.
pointset uniform_pointset(const display_geometry& display, double fraction, const knn_params& knn,
                          knn_storage storage = knn_storage::table);

}  // namespace fov
