#include "fov/dart_throwing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "fov/random.h"

namespace fov {

namespace {

// One square tile of the canvas with its own acceleration grid. Cells are small
// enough (diagonal below the tile's smallest spacing) that each holds at most one
// point, so a cell is just that point's position, or NaN when empty.
struct tile {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // canvas rectangle [x0, x1) x [y0, y1)
  float cell = 1;
  int nx = 0, ny = 0;
  std::vector<float> cx, cy;  // per cell; NaN = empty
  std::vector<point> points;  // accepted, in acceptance order
  std::vector<uint8_t> levels;  // each point's level (nested sets)
  uint64_t darts = 0;
};

class dart_board {
 public:
  // Darts keep `model`'s spacing (set_model changes it); tiles are as wide as the largest
  // spacing of `widest` (the coarsest model a nested set throws), cells fit `model`'s smallest.
  dart_board(const spacing_model& model, const dart_params& params, const spacing_model& widest)
      : model_(model), params_(params), grid_(model, params) {
    const double w = model.display.width, h = model.display.height;
    grid_radius_ = grid_radius(model, params);
    canvas_w_ = float(2 * w);
    canvas_h_ = float(2 * h);
    cx_ = w;
    cy_ = h;
    const double p_max = point_spacing_px(widest, std::hypot(w, h));
    tile_size_ = float(std::max(32.0, std::ceil(p_max)));
    tiles_x_ = int(std::ceil(canvas_w_ / tile_size_));
    tiles_y_ = int(std::ceil(canvas_h_ / tile_size_));
    tiles_.resize(size_t(tiles_x_) * tiles_y_);
    for (int ty = 0; ty < tiles_y_; ++ty)
      for (int tx = 0; tx < tiles_x_; ++tx) {
        tile& t = tiles_[size_t(ty) * tiles_x_ + tx];
        t.x0 = tx * tile_size_;
        t.y0 = ty * tile_size_;
        t.x1 = std::min(canvas_w_, (tx + 1) * tile_size_);
        t.y1 = std::min(canvas_h_, (ty + 1) * tile_size_);
        // Closest distance from the gaze centre to the tile gives its smallest spacing.
        const double dx = std::max({0.0, double(t.x0) - cx_, cx_ - double(t.x1)});
        const double dy = std::max({0.0, double(t.y0) - cy_, cy_ - double(t.y1)});
        const double p_min = point_spacing_px(model, std::hypot(dx, dy));
        // Grid points lie 1 px apart: cells that may hold one must be smaller than that too.
        const bool grid_reach = std::hypot(dx, dy) <= grid_radius_ + 1;
        t.cell = float(0.99 * (grid_reach ? std::min(p_min, 1.0) : p_min) / std::sqrt(2.0));
        t.nx = std::max(1, int(std::ceil((t.x1 - t.x0) / t.cell)));
        t.ny = std::max(1, int(std::ceil((t.y1 - t.y0) / t.cell)));
        const size_t cells = size_t(t.nx) * t.ny;
        if (cells > (size_t(1) << 31)) throw std::runtime_error("spacing too small for the grid");
        t.cx.assign(cells, std::numeric_limits<float>::quiet_NaN());
        t.cy.assign(cells, std::numeric_limits<float>::quiet_NaN());
      }
  }

  // One point at the centre of every grid pixel (is_grid_pixel), spacing 1 px, before any
  // dart: darts then keep their own spacing from them and never land inside a grid pixel.
  uint64_t place_grid() {
    if (grid_radius_ < 0) return 0;
    const int w = model_.display.width, h = model_.display.height;
    const int r = int(std::ceil(grid_radius_)) + 1;
    uint64_t placed = 0;
    for (int py = std::max(0, h - r); py < std::min(2 * h, h + r); ++py)
      for (int px = std::max(0, w - r); px < std::min(2 * w, w + r); ++px) {
        if (!is_grid_pixel(model_, params_, uint32_t(px), uint32_t(py))) continue;
        const float x = float(px) + 0.5f, y = float(py) + 0.5f;
        const int tx = int(x / tile_size_), ty = int(y / tile_size_);
        insert(tiles_[size_t(ty) * tiles_x_ + tx], x, y, 1.0f);
        ++placed;
      }
    return placed;
  }

  // True inside a grid pixel, where no dart may land (grid_test::in_grid_pixel).
  bool in_grid(float x, float y) const { return grid_.in_grid_pixel(x, y); }

  // The spacing darts keep from now on (a nested set's next level): never smaller than the
  // spacing the cells were made for.
  void set_model(const spacing_model& m, uint8_t level) { model_ = m, level_ = level; }

  float spacing_at(float x, float y) const {
    return float(point_spacing_px(model_, std::hypot(double(x) - cx_, double(y) - cy_)));
  }

  // True when some accepted point lies closer than p to (x, y).
  bool conflicts(float x, float y, float p) const {
    const double pp = double(p) * double(p);
    const int tx0 = std::max(0, int(std::floor((x - p) / tile_size_)));
    const int tx1 = std::min(tiles_x_ - 1, int(std::floor((x + p) / tile_size_)));
    const int ty0 = std::max(0, int(std::floor((y - p) / tile_size_)));
    const int ty1 = std::min(tiles_y_ - 1, int(std::floor((y + p) / tile_size_)));
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        const tile& t = tiles_[size_t(ty) * tiles_x_ + tx];
        const int i0 = std::clamp(int(std::floor((x - p - t.x0) / t.cell)), 0, t.nx - 1);
        const int i1 = std::clamp(int(std::floor((x + p - t.x0) / t.cell)), 0, t.nx - 1);
        const int j0 = std::clamp(int(std::floor((y - p - t.y0) / t.cell)), 0, t.ny - 1);
        const int j1 = std::clamp(int(std::floor((y + p - t.y0) / t.cell)), 0, t.ny - 1);
        for (int j = j0; j <= j1; ++j) {
          const float* rx = &t.cx[size_t(j) * t.nx];
          const float* ry = &t.cy[size_t(j) * t.nx];
          for (int i = i0; i <= i1; ++i) {
            if (std::isnan(rx[i])) continue;
            const double dx = double(rx[i]) - x, dy = double(ry[i]) - y;
            if (dx * dx + dy * dy < pp) return true;
          }
        }
      }
    return false;
  }

  void insert(tile& t, float x, float y, float p) {
    const int i = std::min(t.nx - 1, int((x - t.x0) / t.cell));
    const int j = std::min(t.ny - 1, int((y - t.y0) / t.cell));
    const size_t c = size_t(j) * t.nx + i;
    // Two points in one cell would be closer than the tile's smallest spacing:
    // impossible while the model's spacing grows with distance (checked in validate()).
    if (!std::isnan(t.cx[c])) throw std::logic_error("dart grid cell already occupied");
    t.cx[c] = x;
    t.cy[c] = y;
    t.points.push_back({x, y, p});
    t.levels.push_back(level_);
  }

  // Throws darts into the part of tile t inside [rx0, rx1) x [ry0, ry1) until
  // `saturation` consecutive darts are rejected.
  void fill(tile& t, float rx0, float ry0, float rx1, float ry1, uint32_t saturation, rng& r) {
    const float x0 = std::max(t.x0, rx0), x1 = std::min(t.x1, rx1);
    const float y0 = std::max(t.y0, ry0), y1 = std::min(t.y1, ry1);
    if (!(x0 < x1 && y0 < y1)) return;
    uint32_t rejected = 0;
    while (rejected < saturation) {
      float x = float(x0 + r.uniform() * (double(x1) - x0));
      float y = float(y0 + r.uniform() * (double(y1) - y0));
      if (x >= x1) x = std::nextafter(x1, x0);
      if (y >= y1) y = std::nextafter(y1, y0);
      ++t.darts;
      const float p = spacing_at(x, y);
      if (in_grid(x, y) || conflicts(x, y, p)) {
        ++rejected;
      } else {
        insert(t, x, y, p);
        rejected = 0;
      }
    }
  }

  // One phase over a region: four passes, each over tiles that share no neighbour.
  void phase(int phase_id, float rx0, float ry0, float rx1, float ry1, const dart_params& params) {
    for (int pass = 0; pass < 4; ++pass) {
      const int ox = pass & 1, oy = pass >> 1;
      const int nx = (tiles_x_ - ox + 1) / 2, ny = (tiles_y_ - oy + 1) / 2;
      tbb::parallel_for(tbb::blocked_range<int>(0, nx * ny, 1), [&](const tbb::blocked_range<int>& range) {
        for (int n = range.begin(); n < range.end(); ++n) {
          const int tx = ox + 2 * (n % nx), ty = oy + 2 * (n / nx);
          const size_t id = size_t(ty) * tiles_x_ + tx;
          rng r(stream_seed(params.seed, uint64_t(phase_id), id));
          fill(tiles_[id], rx0, ry0, rx1, ry1, params.saturation_rejections, r);
        }
      });
    }
  }

  uint64_t point_count() const {
    uint64_t n = 0;
    for (const tile& t : tiles_) n += t.points.size();
    return n;
  }
  uint64_t darts() const {
    uint64_t n = 0;
    for (const tile& t : tiles_) n += t.darts;
    return n;
  }

  uint64_t probe_free(uint64_t seed, uint32_t probes) const {
    const uint32_t chunk = 4096;
    const uint32_t chunks = (probes + chunk - 1) / chunk;
    return tbb::parallel_reduce(
        tbb::blocked_range<uint32_t>(0, chunks), uint64_t(0),
        [&](const tbb::blocked_range<uint32_t>& range, uint64_t acc) {
          for (uint32_t c = range.begin(); c < range.end(); ++c) {
            rng r(stream_seed(seed, 0xF4EEu, c));
            const uint32_t n = std::min(chunk, probes - c * chunk);
            for (uint32_t i = 0; i < n; ++i) {
              float x = float(r.uniform() * canvas_w_), y = float(r.uniform() * canvas_h_);
              x = std::min(x, std::nextafter(canvas_w_, 0.f));
              y = std::min(y, std::nextafter(canvas_h_, 0.f));
              if (!in_grid(x, y) && !conflicts(x, y, spacing_at(x, y))) ++acc;
            }
          }
          return acc;
        },
        [](uint64_t a, uint64_t b) { return a + b; });
  }

  std::vector<point> take_points() {
    std::vector<point> all;
    all.reserve(point_count());
    for (tile& t : tiles_) all.insert(all.end(), t.points.begin(), t.points.end());
    return all;
  }

  std::vector<point> take_points_with_levels(std::vector<uint8_t>& levels) {
    levels.clear();
    levels.reserve(point_count());
    for (const tile& t : tiles_) levels.insert(levels.end(), t.levels.begin(), t.levels.end());
    return take_points();
  }

  float canvas_w_, canvas_h_;
  double cx_, cy_;

 private:
  spacing_model model_;
  dart_params params_;
  uint8_t level_ = 0;  // the level darts are accepted into
  grid_test grid_;
  double grid_radius_ = -1;
  float tile_size_;
  int tiles_x_, tiles_y_;
  std::vector<tile> tiles_;
};

}  // namespace

uint64_t morton_code(float x, float y) {
  auto spread = [](uint64_t v) {
    v &= 0xFFFFFFFFull;
    v = (v | (v << 16)) & 0x0000FFFF0000FFFFull;
    v = (v | (v << 8)) & 0x00FF00FF00FF00FFull;
    v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0Full;
    v = (v | (v << 2)) & 0x3333333333333333ull;
    v = (v | (v << 1)) & 0x5555555555555555ull;
    return v;
  };
  const auto qx = uint64_t(std::max(0.0, double(x) * 64.0));
  const auto qy = uint64_t(std::max(0.0, double(y) * 64.0));
  return spread(qx) | (spread(qy) << 1);
}

namespace {

// The order sort_morton puts points in: order[j] is the index of the j-th.
std::vector<uint32_t> morton_order(const std::vector<point>& points) {
  std::vector<std::pair<uint64_t, uint32_t>> keys(points.size());
  for (size_t i = 0; i < points.size(); ++i) keys[i] = {morton_code(points[i].x, points[i].y), uint32_t(i)};
  std::sort(keys.begin(), keys.end(), [&](const auto& a, const auto& b) {
    if (a.first != b.first) return a.first < b.first;
    const point &pa = points[a.second], &pb = points[b.second];
    if (pa.y != pb.y) return pa.y < pb.y;
    if (pa.x != pb.x) return pa.x < pb.x;
    return a.second < b.second;
  });
  std::vector<uint32_t> order(points.size());
  for (size_t i = 0; i < keys.size(); ++i) order[i] = keys[i].second;
  return order;
}

void check_dart_params(const spacing_model& model, const dart_params& params) {
  if (const std::string why = validate(model); !why.empty()) throw std::invalid_argument(why);
  if (params.saturation_rejections == 0) throw std::invalid_argument("saturation_rejections must be positive");
  if (!(params.central_fraction >= 0 && params.central_fraction <= 2))
    throw std::invalid_argument("central_fraction must lie in [0, 2]");
  if (params.fovea == fovea_layout::grid && !valid_grid_spacing(params.grid_spacing))
    throw std::invalid_argument(fmt::format("grid_spacing must lie in {}..{} pixels", min_grid_spacing, max_grid_spacing));
}

void probe(const dart_board& board, const dart_params& params, dart_stats& s) {
  if (params.free_area_probes > 0) {
    s.free_probes_accepted = board.probe_free(params.seed, params.free_area_probes);
    s.free_fraction = double(s.free_probes_accepted) / params.free_area_probes;
  }
}

}  // namespace

void sort_morton(std::vector<point>& points) {
  const std::vector<uint32_t> order = morton_order(points);
  std::vector<point> sorted(points.size());
  for (size_t i = 0; i < order.size(); ++i) sorted[i] = points[order[i]];
  points.swap(sorted);
}

std::vector<point> throw_darts(const spacing_model& model, const dart_params& params, dart_stats* stats) {
  check_dart_params(model, params);
  const auto start = std::chrono::steady_clock::now();
  dart_board board(model, params, model);
  const uint64_t grid = board.place_grid();
  board.phase(1, 0, 0, board.canvas_w_, board.canvas_h_, params);
  const uint64_t after_phase1 = board.point_count();
  const double hw = 0.5 * params.central_fraction * model.display.width;
  const double hh = 0.5 * params.central_fraction * model.display.height;
  if (params.central_fraction > 0)
    board.phase(2, float(board.cx_ - hw), float(board.cy_ - hh), float(board.cx_ + hw), float(board.cy_ + hh),
                params);
  dart_stats s;
  s.grid_points = grid;
  s.phase1_points = after_phase1 - grid;
  s.phase2_points = board.point_count() - after_phase1;
  s.darts_thrown = board.darts();
  probe(board, params, s);
  std::vector<point> points = board.take_points();
  sort_morton(points);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = s;
  return points;
}

std::string levels_problem(const std::vector<double>& scales) {
  if (scales.size() < 2 || scales.size() > max_levels)
    return fmt::format("--levels needs 2..{} scales (got {})", max_levels, scales.size());
  for (size_t i = 0; i < scales.size(); ++i) {
    if (!(scales[i] > 0) || !std::isfinite(scales[i]))
      return fmt::format("--levels: scale {} must be positive and finite (got {})", i + 1, scales[i]);
    if (i > 0 && !(scales[i] > scales[i - 1]))
      return fmt::format("--levels must increase, finest first (got {} after {})", scales[i], scales[i - 1]);
  }
  return "";
}

nested_points throw_nested_darts(const spacing_model& model, const std::vector<double>& scales, const dart_params& params,
                                 dart_stats* stats) {
  if (const std::string why = levels_problem(scales); !why.empty()) throw std::invalid_argument(why);
  if (params.fovea != fovea_layout::darts) throw std::invalid_argument("nested sets throw darts everywhere (no grid fovea)");
  spacing_model finest = model, coarsest = model;
  finest.scale = scales.front();
  coarsest.scale = scales.back();
  check_dart_params(finest, params);
  check_dart_params(coarsest, params);
  const auto start = std::chrono::steady_clock::now();
  dart_board board(finest, params, coarsest);
  const uint32_t levels = uint32_t(scales.size());
  dart_stats s;
  for (uint32_t l = 0; l < levels; ++l) {
    spacing_model m = model;
    m.scale = scales[levels - 1 - l];  // level 0 is the coarsest: the largest scale
    board.set_model(m, uint8_t(l));
    const uint64_t before = board.point_count();
    board.phase(int(2 * l + 1), 0, 0, board.canvas_w_, board.canvas_h_, params);
    const uint64_t after_phase1 = board.point_count();
    const double hw = 0.5 * params.central_fraction * model.display.width;
    const double hh = 0.5 * params.central_fraction * model.display.height;
    if (params.central_fraction > 0)
      board.phase(int(2 * l + 2), float(board.cx_ - hw), float(board.cy_ - hh), float(board.cx_ + hw),
                  float(board.cy_ + hh), params);
    s.phase1_points += after_phase1 - before;
    s.phase2_points += board.point_count() - after_phase1;
  }
  s.darts_thrown = board.darts();
  probe(board, params, s);  // at the finest level's spacing
  nested_points out;
  std::vector<point> all = board.take_points_with_levels(out.level);
  const std::vector<uint32_t> order = morton_order(all);
  out.points.resize(all.size());
  std::vector<uint8_t> level(all.size());
  for (size_t i = 0; i < order.size(); ++i) out.points[i] = all[order[i]], level[i] = out.level[order[i]];
  out.level.swap(level);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = s;
  return out;
}

}  // namespace fov
