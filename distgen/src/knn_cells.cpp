#include "fov/knn_cells.h"

#include "fov/files.h"
#include "fov/knn_table.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <flann/flann.hpp>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "knn_rank.h"

namespace fov {

namespace {

using knn_rank::distance2;
using knn_rank::extra_candidates;
using knn_rank::ranked;

// The farthest a pixel centre of a cell of 2^level pixels lies from the cell's centre.
double cell_delta(uint32_t level) { return double((1u << level) - 1) * std::sqrt(0.5); }

// One coordinate of the centre of the cell of 2^level pixels that holds canvas pixel p.
double cell_centre(uint32_t p, uint32_t level) { return double((p >> level) << level) + 0.5 * double(1u << level); }

// FLANN searches in float: its radius is widened by this much (pixels) and its k-th
// neighbour re-ranked in double, so that no candidate the bound asks for is lost.
constexpr double flann_slack = 0.01;

// Each tile's level from the smallest spacing of the points inside it.
std::vector<uint32_t> tile_levels(const std::vector<point>& points, uint32_t width, uint32_t height, double fraction) {
  const uint32_t tile = knn_cells::tile, tx = (width + tile - 1) / tile, ty = (height + tile - 1) / tile;
  std::vector<float> smallest(size_t(tx) * ty, std::numeric_limits<float>::infinity());
  for (const point& p : points) {
    if (!(p.x >= 0 && p.y >= 0 && p.x < float(width) && p.y < float(height))) continue;
    float& s = smallest[size_t(uint32_t(p.y) / tile) * tx + uint32_t(p.x) / tile];
    s = std::min(s, p.spacing);
  }
  std::vector<uint32_t> level(smallest.size());
  for (size_t t = 0; t < level.size(); ++t) {
    const double side = fraction * double(smallest[t]);
    uint32_t l = 0;
    while (l < knn_cells::max_level && double(2u << l) <= side) ++l;
    level[t] = l;
  }
  return level;
}

uint64_t cells_of(const std::vector<uint32_t>& level) {
  uint64_t n = 0;
  for (uint32_t l : level) n += uint64_t(knn_cells::tile >> l) * (knn_cells::tile >> l);
  return n;
}

}  // namespace

uint64_t count_knn_cells(const std::vector<point>& points, uint32_t width, uint32_t height, double cell_fraction) {
  return cells_of(tile_levels(points, width, height, cell_fraction));
}

knn_cells build_knn_cells(const std::vector<point>& points, uint32_t width, uint32_t height,
                          const knn_cells_params& params) {
  if (params.k < 1 || params.k > max_knn)
    throw std::invalid_argument(fmt::format("k must lie in 1..{} (got {})", max_knn, params.k));
  if (points.size() < params.k)
    throw std::invalid_argument(fmt::format("k = {} exceeds the {} points of the set; lower k", params.k, points.size()));
  if (points.size() >= (uint64_t(1) << 32)) throw std::invalid_argument("more than 2^32 points");
  if (!(params.cell_fraction > 0 && params.cell_fraction <= 64))
    throw std::invalid_argument(fmt::format("cell fraction must lie in (0, 64], got {}", params.cell_fraction));
  knn_cells cells;
  cells.width = width;
  cells.height = height;
  cells.k = params.k;
  const uint32_t tx = cells.tiles_x(), tile = knn_cells::tile;

  const std::vector<uint32_t> level = tile_levels(points, width, height, params.cell_fraction);
  // Cells cost 4 bytes each and about k candidates of 4 bytes (more in the fovea): checked
  // before anything is built (a file's points may claim any spacing).
  const uint64_t cell_total = cells_of(level);
  if (cell_total >= (uint64_t(1) << 29)) throw std::invalid_argument("more than 2^29 cells; raise the cell fraction");
  if (const std::string why = memory_problem(cell_total * 4 * (1 + 2 * uint64_t(params.k)),
                                             fmt::format("the k-NN cells of a {}x{} canvas (k = {})", width, height, params.k));
      !why.empty())
    throw std::invalid_argument(why);

  flann::Matrix<float> dataset(const_cast<float*>(&points[0].x), points.size(), 2, sizeof(point));
  flann::Index<flann::L2_Simple<float>> index(dataset, flann::KDTreeSingleIndexParams(10));
  index.buildIndex();

  // Every tile's candidates, built in parallel, then laid end to end.
  std::vector<std::vector<uint32_t>> tile_candidates(level.size()), tile_starts(level.size());
  const uint32_t kq = uint32_t(std::min<size_t>(points.size(), params.k + extra_candidates));
  std::atomic<uint64_t> kept{0};  // candidates so far, against params.max_candidates
  std::atomic<bool> too_many{false};
  tbb::parallel_for(size_t(0), level.size(), [&](size_t t) {
    if (too_many.load(std::memory_order_relaxed)) return;
    flann::SearchParams search(flann::FLANN_CHECKS_UNLIMITED, 0, true);
    search.cores = 1;
    std::vector<size_t> found(kq);
    std::vector<float> dists(kq);
    std::vector<std::vector<size_t>> near_idx;
    std::vector<std::vector<float>> near_dist;
    std::vector<ranked> rank;
    const uint32_t l = level[t], size = 1u << l, side = tile >> l;
    const uint32_t x0 = uint32_t(t % tx) * tile, y0 = uint32_t(t / tx) * tile;
    const double delta = cell_delta(l);
    std::vector<uint32_t>& out = tile_candidates[t];
    std::vector<uint32_t>& starts = tile_starts[t];
    starts.reserve(size_t(side) * side);
    for (uint32_t cy = 0; cy < side; ++cy)
      for (uint32_t cx = 0; cx < side; ++cx) {
        starts.push_back(uint32_t(out.size()));
        const double c[2] = {cell_centre(x0 + cx * size, l), cell_centre(y0 + cy * size, l)};
        float q[2] = {float(c[0]), float(c[1])};  // exact: halves of integers below 2^24
        flann::Matrix<float> query(q, 1, 2);
        flann::Matrix<size_t> idx(found.data(), 1, kq);
        flann::Matrix<float> dst(dists.data(), 1, kq);
        index.knnSearch(query, idx, dst, kq, search);
        rank.clear();
        for (uint32_t j = 0; j < kq; ++j) rank.push_back({distance2(points[found[j]], c[0], c[1]), uint32_t(found[j])});
        std::nth_element(rank.begin(), rank.begin() + (params.k - 1), rank.end());
        const double radius = std::sqrt(rank[params.k - 1].d2) + 2 * delta + flann_slack;
        index.radiusSearch(query, near_idx, near_dist, float(radius * radius), search);
        rank.clear();
        for (size_t i : near_idx[0]) rank.push_back({distance2(points[i], c[0], c[1]), uint32_t(i)});
        std::sort(rank.begin(), rank.end());
        for (const ranked& r : rank) out.push_back(r.index);
        if (params.max_candidates && kept.fetch_add(rank.size(), std::memory_order_relaxed) + rank.size() > params.max_candidates) {
          too_many = true;
          return;
        }
      }
  });

  if (too_many)
    throw std::invalid_argument(fmt::format("the k-NN cells of these {} points would hold more than {} candidates (refused)",
                                            points.size(), params.max_candidates));
  size_t candidate_total = 0;
  for (size_t t = 0; t < level.size(); ++t) candidate_total += tile_candidates[t].size();
  if (candidate_total >= (uint64_t(1) << 32)) throw std::invalid_argument("more than 2^32 candidates; raise the cell fraction");
  cells.tiles.resize(level.size());
  cells.cell_start.resize(cell_total + 1);
  cells.candidates.resize(candidate_total);
  size_t cell_at = 0, candidate_at = 0;
  for (size_t t = 0; t < level.size(); ++t) {
    cells.tiles[t] = uint32_t(cell_at) << 3 | level[t];
    for (uint32_t s : tile_starts[t]) cells.cell_start[cell_at++] = uint32_t(candidate_at + s);
    std::copy(tile_candidates[t].begin(), tile_candidates[t].end(), cells.candidates.begin() + long(candidate_at));
    candidate_at += tile_candidates[t].size();
  }
  cells.cell_start[cell_at] = uint32_t(candidate_at);
  set_cells_radii(cells, points);
  return cells;
}

void set_cells_radii(knn_cells& cells, const std::vector<point>& points) {
  const uint32_t k = cells.k, tile = knn_cells::tile, tx = cells.tiles_x();
  cells.radius_by_tile.assign(cells.tiles.size() * k, 0.0f);
  tbb::parallel_for(size_t(0), cells.tiles.size(), [&](size_t t) {
    const uint32_t l = cells.tiles[t] & 7u, size = 1u << l, side = tile >> l;
    const double delta = cell_delta(l);
    float* r = cells.radius_by_tile.data() + t * k;
    for (uint32_t c = 0; c < side * side; ++c) {
      const uint32_t cell = (cells.tiles[t] >> 3) + c;
      const double cx = cell_centre(uint32_t(t % tx) * tile + (c % side) * size, l);
      const double cy = cell_centre(uint32_t(t / tx) * tile + (c / side) * size, l);
      for (uint32_t j = 0; j < k; ++j) {
        const double d = std::sqrt(distance2(points[cells.candidates[cells.cell_start[cell] + j]], cx, cy)) + delta;
        r[j] = std::max(r[j], std::nextafter(float(d), std::numeric_limits<float>::infinity()));
      }
    }
    for (uint32_t j = 1; j < k; ++j) r[j] = std::max(r[j], r[j - 1]);
  });
  cells.radius_by_rank.assign(k, 0.0f);
  for (size_t i = 0; i < cells.radius_by_tile.size(); ++i)
    cells.radius_by_rank[i % k] = std::max(cells.radius_by_rank[i % k], cells.radius_by_tile[i]);
  cells.max_radius = cells.radius_by_rank.back();
}

uint32_t cell_neighbours(const knn_cells& cells, const std::vector<point>& points, uint32_t x, uint32_t y, uint32_t k,
                         uint32_t* out) {
  const uint32_t tile = knn_cells::tile;
  const uint32_t v = cells.tiles[size_t(y / tile) * cells.tiles_x() + x / tile];
  const uint32_t l = v & 7u, side = tile >> l;
  const uint32_t cell = (v >> 3) + ((y % tile) >> l) * side + ((x % tile) >> l);
  const double cx = cell_centre(x, l), cy = cell_centre(y, l);
  const double qx = double(x) + 0.5, qy = double(y) + 0.5;
  const uint32_t a = cells.cell_start[cell], b = cells.cell_start[cell + 1];
  // The prefix of candidates that can hold the pixel's k nearest (header).
  const double reach = std::sqrt(distance2(points[cells.candidates[a + k - 1]], cx, cy)) + 2 * cell_delta(l);
  const double reach2 = reach * reach * (1 + 1e-12) + 1e-12;
  ranked best[max_knn];
  uint32_t n = 0, ranked_count = 0;
  for (uint32_t at = a; at < b; ++at) {
    const uint32_t i = cells.candidates[at];
    const point& p = points[i];
    if (distance2(p, cx, cy) > reach2) break;
    ++ranked_count;
    const ranked r{distance2(p, qx, qy), i};
    if (n == k && !(r < best[k - 1])) continue;
    uint32_t j = n < k ? n++ : k - 1;
    for (; j > 0 && r < best[j - 1]; --j) best[j] = best[j - 1];
    best[j] = r;
  }
  for (uint32_t j = 0; j < k; ++j) out[j] = best[j].index;
  return ranked_count;
}

void rect_neighbour_points(const knn_cells& cells, const std::vector<point>& points, uint32_t x0, uint32_t y0,
                           uint32_t x1, uint32_t y1, uint32_t k, std::vector<uint32_t>& out) {
  x1 = std::min(x1, cells.width), y1 = std::min(y1, cells.height);
  if (x0 >= x1 || y0 >= y1 || k < 1 || k > cells.k) return;
  const uint32_t tile = knn_cells::tile, tx = cells.tiles_x();
  for (uint32_t ty = y0 / tile; ty <= (y1 - 1) / tile; ++ty)
    for (uint32_t tx0 = x0 / tile; tx0 <= (x1 - 1) / tile; ++tx0) {
      const uint32_t v = cells.tiles[size_t(ty) * tx + tx0];
      const uint32_t l = v & 7u, side = tile >> l;
      // The tile's cells that meet the rectangle.
      const uint32_t cx0 = (std::max(x0, tx0 * tile) - tx0 * tile) >> l, cx1 = (std::min(x1, (tx0 + 1) * tile) - 1 - tx0 * tile) >> l;
      const uint32_t cy0 = (std::max(y0, ty * tile) - ty * tile) >> l, cy1 = (std::min(y1, (ty + 1) * tile) - 1 - ty * tile) >> l;
      for (uint32_t cy = cy0; cy <= cy1; ++cy)
        for (uint32_t cx = cx0; cx <= cx1; ++cx) {
          const uint32_t cell = (v >> 3) + cy * side + cx;
          const double ccx = cell_centre(tx0 * tile + (cx << l), l), ccy = cell_centre(ty * tile + (cy << l), l);
          const uint32_t a = cells.cell_start[cell], b = cells.cell_start[cell + 1];
          // cell_neighbours's prefix: every pixel of the cell finds its k nearest in it.
          const double reach = std::sqrt(distance2(points[cells.candidates[a + k - 1]], ccx, ccy)) + 2 * cell_delta(l);
          const double reach2 = reach * reach * (1 + 1e-12) + 1e-12;
          for (uint32_t at = a; at < b; ++at) {
            const uint32_t i = cells.candidates[at];
            if (distance2(points[i], ccx, ccy) > reach2) break;
            out.push_back(i);
          }
        }
    }
}

std::string knn_cells_problem(const knn_cells& cells, size_t point_count) {
  if (cells.k < 1 || cells.k > max_knn) return fmt::format("k = {} outside 1..{}", cells.k, max_knn);
  if (cells.tiles.size() != uint64_t(cells.tiles_x()) * cells.tiles_y())
    return fmt::format("{} tiles for a {}x{} canvas", cells.tiles.size(), cells.width, cells.height);
  if (cells.cell_start.empty()) return "no cells";
  const uint64_t n_cells = cells.cell_count();
  uint64_t expected = 0;
  for (size_t t = 0; t < cells.tiles.size(); ++t) {
    const uint32_t l = cells.tiles[t] & 7u;
    if (l > knn_cells::max_level) return fmt::format("tile {} has level {} (at most {})", t, l, knn_cells::max_level);
    const uint32_t side = knn_cells::tile >> l;
    if ((cells.tiles[t] >> 3) != expected) return fmt::format("tile {}'s cells do not follow the previous tile's", t);
    expected += uint64_t(side) * side;
  }
  if (expected != n_cells) return fmt::format("{} cells where the tiles hold {}", n_cells, expected);
  if (cells.cell_start[0] != 0 || cells.cell_start.back() != cells.candidates.size())
    return "cell offsets do not span the candidates";
  for (uint64_t c = 0; c < n_cells; ++c)
    if (cells.cell_start[c + 1] < cells.cell_start[c] + cells.k)
      return fmt::format("cell {} holds fewer than k = {} candidates", c, cells.k);
  for (uint32_t i : cells.candidates)
    if (i >= point_count) return fmt::format("a candidate names point {} of {}", i, point_count);
  return "";
}

}  // namespace fov
