#include "fov/nested.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include <fmt/format.h>

#include "fov/knn_cells.h"

namespace fov {

uint64_t nested_levels::bytes() const {
  uint64_t n = 0;
  for (size_t l = 0; l < levels.size(); ++l) {
    const set_level& v = levels[l];
    n += 4 * uint64_t(v.global.size());
    if (l + 1 < levels.size()) n += v.set->cells.bytes() + sizeof(point) * uint64_t(v.set->points.size());
  }
  return n;
}

std::vector<point> level_points(const pointset& set, uint32_t l) {
  if (!set.nested()) return set.points;
  std::vector<point> out;
  for (size_t i = 0; i < set.points.size(); ++i)
    if (set.level[i] <= l) out.push_back(set.points[i]);
  return out;
}

void level_rect_points(const set_level& level, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, uint32_t k,
                       std::vector<uint32_t>& out) {
  const pointset& set = *level.set;
  if (set.cells.loaded()) return rect_neighbour_points(set.cells, set.points, x0, y0, x1, y1, k, out);
  const knn_table& t = set.table;
  x1 = std::min(x1, t.width), y1 = std::min(y1, t.height);
  k = std::min(k, t.k);
  for (uint32_t y = y0; y < y1; ++y)
    for (uint32_t x = x0; x < x1; ++x)
      for (uint32_t j = 0; j < k; ++j) out.push_back(t.at(x, y, j));
}

nested_levels make_levels(std::shared_ptr<const pointset> set) {
  require_neighbours(*set);
  const auto start = std::chrono::steady_clock::now();
  nested_levels out;
  const uint32_t count = set->level_count();
  if (set->nested() && set->level.size() != set->points.size())
    throw std::invalid_argument("a nested set's levels do not match its points");
  knn_cells_params cp;
  cp.k = stored_k(*set);
  for (uint32_t l = 0; l < count; ++l) {
    set_level v;
    v.scale = set->nested() ? set->level_scales[l] : set->model.scale;
    if (l + 1 == count) {
      v.set = set;
      v.global.resize(set->points.size());
      for (uint32_t i = 0; i < v.global.size(); ++i) v.global[i] = i;
    } else {
      auto level = std::make_shared<pointset>();
      level->model = set->model;
      level->model.scale = v.scale;
      level->darts = set->darts;
      for (uint32_t i = 0; i < set->points.size(); ++i)
        if (set->level[i] <= l) level->points.push_back(set->points[i]), v.global.push_back(i);
      if (level->points.size() < cp.k)
        throw std::invalid_argument(fmt::format("level {} holds {} points, fewer than k = {}", l, level->points.size(), cp.k));
      level->cells = build_knn_cells(level->points, set->canvas_width(), set->canvas_height(), cp);
      v.set = std::move(level);
    }
    out.levels.push_back(std::move(v));
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace fov
