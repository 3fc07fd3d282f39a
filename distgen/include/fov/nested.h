// The levels of a nested set (fovgen --levels) as sets of their own. Level l holds the
// points of levels 0..l (0 the coarsest): a fixed set at that level's scale, so every tool
// that traces or reconstructs a fixed set works on it unchanged. A frame that refines some
// regions reads, in each region, one level's neighbours, all of which it has traced.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "fov/pointset.h"

namespace fov {

struct set_level {
  double scale = 1;
  // Level l's points (a subsequence of the nested set's, so in Morton order), its model at
  // the level's scale, its darts' parameters. The finest level is the nested set itself
  // (its table or cells); every coarser one holds k-NN cells built here (the nested set's k).
  std::shared_ptr<const pointset> set;
  // set->points[j] is the nested set's point global[j] (ascending).
  std::vector<uint32_t> global;
};

// Appends to `out` (local indices of level.set, possibly repeated) the points that canvas
// pixels in [x0, x1) x [y0, y1) may read among their first k: with a table exactly those (each
// pixel's entries), with cells rect_neighbour_points's superset.
void level_rect_points(const set_level& level, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, uint32_t k,
                       std::vector<uint32_t>& out);

struct nested_levels {
  std::vector<set_level> levels;  // coarsest first; one level (the set itself) for a fixed set
  double seconds = 0;             // wall time to build the coarser levels' cells
  uint64_t bytes() const;         // what the levels add in memory (points, maps, cells)
};

// The levels of `set` (which must hold its neighbours: require_neighbours). Throws
// std::invalid_argument for a nested set whose levels do not match its points.
nested_levels make_levels(std::shared_ptr<const pointset> set);

// The points of a nested set's level l (level l or coarser), as a fixed set's points: for
// fovgen's export of one level and for tests.
std::vector<point> level_points(const pointset& set, uint32_t l);

}  // namespace fov
