#include <sys/mman.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "fov/dart_throwing.h"
#include "fov/knn_cells.h"
#include "fov/knn_table.h"
#include "fov/lattice.h"
#include "fov/pointset.h"

namespace fov {

void* allocate_table_bytes(size_t bytes) {
  const size_t huge = size_t(2) << 20;
  bytes = std::max(huge, (bytes + huge - 1) / huge * huge);
  void* p = std::aligned_alloc(huge, bytes);
  if (!p) throw std::bad_alloc();
  if (bytes >= 2 * huge) madvise(p, bytes, MADV_HUGEPAGE);
  return p;
}

void free_table_bytes(void* p) { std::free(p); }

canvas_offset offset_for_gaze(const display_geometry& display, gaze_point gaze) {
  double gaze_x = gaze.x, gaze_y = gaze.y;
  if (!std::isfinite(gaze_x)) gaze_x = 0.5 * display.width;
  if (!std::isfinite(gaze_y)) gaze_y = 0.5 * display.height;
  gaze_x = std::clamp(gaze_x, 0.0, double(display.width));
  gaze_y = std::clamp(gaze_y, 0.0, double(display.height));
  return {display.width - int(std::floor(gaze_x + 0.5)), display.height - int(std::floor(gaze_y + 0.5))};
}

bool is_grid_pixel(const spacing_model& model, const dart_params& params, uint32_t px, uint32_t py) {
  if (params.fovea != fovea_layout::grid) return false;
  const double dx = px + 0.5 - model.display.width, dy = py + 0.5 - model.display.height;
  return point_spacing_px(model, std::hypot(dx, dy)) <= params.grid_spacing;
}

bool in_grid_pixel(const spacing_model& model, const dart_params& params, float x, float y) {
  if (params.fovea != fovea_layout::grid || !(x >= 0) || !(y >= 0)) return false;
  return is_grid_pixel(model, params, uint32_t(std::floor(x)), uint32_t(std::floor(y)));
}

namespace {

// True when p lies on the centre of canvas pixel (px, py), which it then sets.
bool on_pixel_centre(const point& p, uint32_t& px, uint32_t& py) {
  const float fx = std::floor(p.x), fy = std::floor(p.y);
  if (p.x - fx != 0.5f || p.y - fy != 0.5f) return false;
  px = uint32_t(fx), py = uint32_t(fy);
  return true;
}

}  // namespace

bool is_grid_point(const pointset& set, const point& p) {
  uint32_t px, py;
  return set.darts.fovea == fovea_layout::grid && on_pixel_centre(p, px, py) && is_grid_pixel(set.model, set.darts, px, py);
}

std::string fovea_label(const dart_params& params) {
  if (params.fovea != fovea_layout::grid) return label_of(fovea_layout_labels, params.fovea);
  if (params.grid_spacing == dart_params{}.grid_spacing) return "grid";
  char text[32];
  std::snprintf(text, sizeof text, "grid-%.2f", params.grid_spacing);
  return text;
}

std::string pointset_file_name(const spacing_model& model, const dart_params& darts,
                               const std::vector<double>& level_scales) {
  // The display, then the acuity model where it is not the thesis's CSF (with its parameters
  // where they are not the defaults).
  std::string name = display_name(model.display);
  if (model.acuity.model != acuity_model::wang_csf || !same_acuity(model.acuity, acuity_params{}))
    name += "-" + acuity_label(model.acuity);
  if (darts.sampler != point_sampler::poisson) name += std::string("-") + label_of(point_sampler_labels, darts.sampler);
  if (!level_scales.empty()) {  // given coarsest first, named finest first as --levels lists them
    name += "-n";
    for (size_t l = level_scales.size(); l-- > 0;) {
      char scale[64];
      std::snprintf(scale, sizeof scale, "%.2f", level_scales[l]);
      name += scale + std::string(l > 0 ? "-" : "");
    }
    return name + ".fovset";
  }
  char scale[64];
  std::snprintf(scale, sizeof scale, "%.2f", model.scale);
  return name + "-s" + scale + (darts.fovea == fovea_layout::grid ? "-" + fovea_label(darts) : std::string()) +
         ".fovset";
}

double grid_radius(const spacing_model& model, const dart_params& params) {
  if (params.fovea != fovea_layout::grid || point_spacing_px(model, 0) > params.grid_spacing) return -1;
  double lo = 0, hi = std::hypot(2.0 * model.display.width, 2.0 * model.display.height);
  if (point_spacing_px(model, hi) <= params.grid_spacing) return hi;
  for (int i = 0; i < 64 && hi - lo > 1e-9; ++i) {
    const double mid = 0.5 * (lo + hi);
    (point_spacing_px(model, mid) <= params.grid_spacing ? lo : hi) = mid;
  }
  return lo;
}

grid_test::grid_test(const spacing_model& model, const dart_params& params) : model_(model), params_(params) {
  const double r = grid_radius(model, params);
  if (r < 0) return;
  // Within [r - 1e-6, r + 1e-6] px the test evaluates the model, as is_grid_pixel does.
  inside2_ = std::max(0.0, r - 1e-6) * std::max(0.0, r - 1e-6);
  outside2_ = (r + 1e-6) * (r + 1e-6);
  // A position lies within 0.71 px of its pixel's centre: past r + 1.5, no grid pixel.
  rim_ = r + 1.5;
}

bool grid_test::operator()(const point& p) const {
  uint32_t px, py;
  if (outside2_ < 0 || !on_pixel_centre(p, px, py)) return false;
  const double dx = double(p.x) - model_.display.width, dy = double(p.y) - model_.display.height;
  const double d2 = dx * dx + dy * dy;
  if (d2 < inside2_) return true;
  if (d2 > outside2_) return false;
  return is_grid_pixel(model_, params_, px, py);
}

bool grid_test::in_grid_pixel(float x, float y) const {
  if (rim_ < 0 || std::hypot(double(x) - model_.display.width, double(y) - model_.display.height) > rim_) return false;
  return fov::in_grid_pixel(model_, params_, x, y);
}

uint64_t count_spacing_violations(const std::vector<point>& points, uint32_t canvas_width,
                                  uint32_t canvas_height) {
  if (points.empty()) return 0;
  // Bucket points on a grid of about one point per cell (compressed rows).
  const double area = double(canvas_width) * canvas_height;
  const double cell = std::max(1.0, std::sqrt(area / double(points.size())));
  const auto nx = uint32_t(std::ceil(canvas_width / cell)) + 1, ny = uint32_t(std::ceil(canvas_height / cell)) + 1;
  auto cell_of = [&](float v, uint32_t n) { return std::min<uint32_t>(n - 1, uint32_t(std::max(0.0, v / cell))); };
  std::vector<uint32_t> start(size_t(nx) * ny + 1, 0), order(points.size());
  for (const point& p : points) ++start[size_t(cell_of(p.y, ny)) * nx + cell_of(p.x, nx) + 1];
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (uint32_t i = 0; i < points.size(); ++i)
    order[fill[size_t(cell_of(points[i].y, ny)) * nx + cell_of(points[i].x, nx)]++] = i;

  uint64_t violations = 0;
  for (uint32_t i = 0; i < points.size(); ++i) {
    const point& a = points[i];
    const int r = int(std::ceil(a.spacing / cell));
    const int cx = int(cell_of(a.x, nx)), cy = int(cell_of(a.y, ny));
    for (int y = std::max(0, cy - r); y <= std::min(int(ny) - 1, cy + r); ++y)
      for (int x = std::max(0, cx - r); x <= std::min(int(nx) - 1, cx + r); ++x) {
        const size_t c = size_t(y) * nx + x;
        for (uint32_t s = start[c]; s < start[c + 1]; ++s) {
          const uint32_t j = order[s];
          if (j <= i) continue;
          const point& b = points[j];
          const double dx = double(a.x) - b.x, dy = double(a.y) - b.y;
          const double m = std::min(a.spacing, b.spacing);
          if (dx * dx + dy * dy < m * m) ++violations;
        }
      }
  }
  return violations;
}

void set_knn_radii(knn_table& t, const std::vector<point>& points) {
  t.radius_by_tile.clear();
  t.radius_by_rank.clear();
  t.max_radius = 0;
  if (t.k == 0 || t.entries.empty()) return;
  const uint32_t tile = knn_table::radius_tile, tiles_x = t.radius_tiles_x(), tiles_y = t.radius_tiles_y();
  t.radius_by_tile.assign(size_t(tiles_x) * tiles_y * t.k, 0.0f);
  tbb::parallel_for(uint32_t(0), tiles_x * tiles_y, [&](uint32_t index) {
    float* r = t.radius_by_tile.data() + size_t(index) * t.k;
    const uint32_t x0 = (index % tiles_x) * tile, y0 = (index / tiles_x) * tile;
    for (uint32_t y = y0; y < std::min(t.height, y0 + tile); ++y)
      for (uint32_t x = x0; x < std::min(t.width, x0 + tile); ++x)
        for (uint32_t j = 0; j < t.k; ++j) {
          const point& p = points[t.at(x, y, j)];
          r[j] = std::max(r[j], std::hypot(p.x - (float(x) + 0.5f), p.y - (float(y) + 0.5f)));
        }
    // Over the first j + 1 ranks, not rank j alone: the same for a table in nearest-first
    // order, and still a bound on what a reader of j + 1 ranks reaches in one that is not
    // (a hand-made or imported set), which the traced-point scan relies on.
    for (uint32_t j = 1; j < t.k; ++j) r[j] = std::max(r[j], r[j - 1]);
  });
  t.radius_by_rank.assign(t.k, 0.0f);
  for (size_t i = 0; i < t.radius_by_tile.size(); ++i)
    t.radius_by_rank[i % t.k] = std::max(t.radius_by_rank[i % t.k], t.radius_by_tile[i]);
  t.max_radius = t.radius_by_rank.back();
}

namespace {

bool table_loaded(const pointset& set) {
  const knn_table& t = set.table;
  return t.k != 0 && t.width == set.canvas_width() && t.height == set.canvas_height() &&
         t.entries.size() == t.pixel_count() * t.k;
}

bool cells_loaded(const pointset& set) {
  return set.cells.loaded() && set.cells.width == set.canvas_width() && set.cells.height == set.canvas_height();
}

// The radii the traced-point scan bounds its band with, from the table or the cells.
struct radii {
  uint32_t k = 0;
  const std::vector<float>* by_rank = nullptr;
  const std::vector<float>* by_tile = nullptr;
  float max = 0;
};
radii radii_of(const pointset& set) {
  if (table_loaded(set)) return {set.table.k, &set.table.radius_by_rank, &set.table.radius_by_tile, set.table.max_radius};
  return {set.cells.k, &set.cells.radius_by_rank, &set.cells.radius_by_tile, set.cells.max_radius};
}
static_assert(knn_table::radius_tile == knn_cells::tile, "the radii's tiles are the cells' tiles");

}  // namespace

void require_neighbours(const pointset& set) {
  if (!table_loaded(set) && !cells_loaded(set))
    throw std::invalid_argument("the point set's k-NN table is not loaded");
}

uint32_t stored_k(const pointset& set) { return set.table.k != 0 ? set.table.k : set.cells.k; }

void pixel_neighbours(const pointset& set, uint32_t x, uint32_t y, uint32_t k, uint32_t* out) {
  if (set.table.k != 0) {
    const uint64_t pixel = uint64_t(y) * set.table.width + x;
    for (uint32_t j = 0; j < k; ++j) out[j] = set.table.entries[set.table.offset(pixel, j)];
  } else {
    cell_neighbours(set.cells, set.points, x, y, k, out);
  }
}

std::vector<uint8_t> traced_point_mask(const pointset& set, gaze_point gaze, uint32_t k_used) {
  require_neighbours(set);
  const display_geometry& d = set.model.display;
  const canvas_offset o = offset_for_gaze(d, gaze);
  std::vector<uint8_t> mask(set.points.size(), 0);
  const knn_table& t = set.table;
  const bool table = t.k != 0;
  const radii rad = radii_of(set);
  k_used = std::min(k_used, rad.k);
  // Only pixels within the k_used-th neighbour's largest radius of the screen edge can
  // read an off-screen point (without known radii, every pixel is scanned). Rows are
  // split over threads; each collects the points it finds, and the marks are written after.
  const float radius = rad.by_rank->size() == rad.k ? (*rad.by_rank)[k_used - 1] : rad.max;
  const int band = radius > 0 ? int(std::ceil(radius)) + 1 : std::max(d.width, d.height);
  // Pixels whose tile's radius (rank k_used) stays inside the screen are skipped.
  const uint32_t tile = knn_table::radius_tile;
  const uint32_t tiles_x = (set.canvas_width() + tile - 1) / tile, tiles_y = (set.canvas_height() + tile - 1) / tile;
  const float* tile_radius = rad.by_tile->size() == size_t(tiles_x) * tiles_y * rad.k
                                 ? rad.by_tile->data() + (k_used - 1)
                                 : nullptr;
  // On-screen points first: the band scan then tests a point's byte in the mask (580 KB
  // for the FOVE set, cache-resident) instead of reading its position (16 bytes each).
  tbb::parallel_for(tbb::blocked_range<size_t>(0, set.points.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) mask[i] = on_screen(set.points[i], d, o);
  });
  // Each block of 16 rows collects into its own list (no copies of partial results).
  constexpr int rows_per_block = 16;
  std::vector<std::vector<uint32_t>> referenced(size_t((d.height + rows_per_block - 1) / rows_per_block));
  tbb::parallel_for(size_t(0), referenced.size(), [&](size_t b) {
    std::vector<uint32_t>& acc = referenced[b];
    for (int sy = int(b) * rows_per_block, end = std::min(d.height, sy + rows_per_block); sy < end; ++sy) {
      const bool edge_row = sy < band || sy >= d.height - band;
      const uint64_t row = uint64_t(sy + o.y) * t.width + uint64_t(o.x);  // table only
      for (int sx = 0; sx < d.width; ++sx) {
        if (!edge_row && sx == band && d.width - band > band) sx = d.width - band;  // skip the interior
        if (tile_radius) {  // this pixel's neighbours all lie within its tile's radius
          const int edge = std::min(std::min(sx, d.width - 1 - sx), std::min(sy, d.height - 1 - sy));
          const uint32_t cx = uint32_t(sx + o.x) / knn_table::radius_tile, cy = uint32_t(sy + o.y) / knn_table::radius_tile;
          if (tile_radius[(size_t(cy) * tiles_x + cx) * rad.k] < float(edge)) continue;
        }
        if (table) {
          for (uint32_t j = 0; j < k_used; ++j) {
            const uint32_t i = t.entries[t.offset(row + sx, j)];
            if (!mask[i]) acc.push_back(i);
          }
        } else {
          uint32_t found[max_knn];
          cell_neighbours(set.cells, set.points, uint32_t(sx + o.x), uint32_t(sy + o.y), k_used, found);
          for (uint32_t j = 0; j < k_used; ++j)
            if (!mask[found[j]]) acc.push_back(found[j]);
        }
      }
    }
  });
  for (const std::vector<uint32_t>& block : referenced)
    for (uint32_t i : block) mask[i] = 1;
  return mask;
}

std::vector<uint32_t> traced_points(const pointset& set, gaze_point gaze, uint32_t k_used) {
  const std::vector<uint8_t> mask = traced_point_mask(set, gaze, k_used);
  // Compaction in two parallel passes over fixed blocks: count, then write at each
  // block's prefix sum. The result is the same on any number of threads.
  constexpr size_t block = 16384;
  const size_t blocks = (mask.size() + block - 1) / block;
  std::vector<size_t> start(blocks + 1, 0);
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    const size_t end = std::min(mask.size(), (b + 1) * block);
    start[b + 1] = size_t(std::count(mask.begin() + long(b * block), mask.begin() + long(end), uint8_t(1)));
  });
  for (size_t b = 0; b < blocks; ++b) start[b + 1] += start[b];
  std::vector<uint32_t> out(start[blocks]);
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    size_t at = start[b];
    for (size_t i = b * block, end = std::min(mask.size(), (b + 1) * block); i < end; ++i)
      if (mask[i]) out[at++] = uint32_t(i);
  });
  return out;
}

namespace {

// A half-open rectangle of canvas pixels.
struct pixel_rect {
  int64_t x0, y0, x1, y1;
  bool meets(const pixel_rect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
  bool within(const pixel_rect& o) const { return x0 >= o.x0 && x1 <= o.x1 && y0 >= o.y0 && y1 <= o.y1; }
  bool holds(int64_t x, int64_t y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

constexpr uint64_t low32 = 0xFFFFFFFFull;

// Whether any pixel of `screen` reads point i among its first k_used neighbours.
bool read_on_screen(const pointset& set, const traced_index& index, uint32_t i, const pixel_rect& screen) {
  const traced_index::reach& r = index.reaches[i];
  const int64_t min_x = int64_t(r.min_x >> 32), max_x = int64_t(r.max_x >> 32);
  const int64_t min_y = int64_t(r.min_y >> 32), max_y = int64_t(r.max_y >> 32);
  if (min_x > max_x) return false;  // no pixel reads it
  const pixel_rect box{min_x, min_y, max_x + 1, max_y + 1};
  if (!box.meets(screen)) return false;
  if (screen.holds(min_x, int64_t(r.min_x & low32)) || screen.holds(max_x, int64_t(r.max_x & low32)) ||
      screen.holds(int64_t(r.min_y & low32), min_y) || screen.holds(int64_t(r.max_y & low32), max_y))
    return true;
  // Near a corner of the screen: read the box's on-screen pixels.
  uint32_t found[max_knn];
  for (int64_t y = std::max(box.y0, screen.y0); y < std::min(box.y1, screen.y1); ++y)
    for (int64_t x = std::max(box.x0, screen.x0); x < std::min(box.x1, screen.x1); ++x) {
      pixel_neighbours(set, uint32_t(x), uint32_t(y), index.k_used, found);
      for (uint32_t j = 0; j < index.k_used; ++j)
        if (found[j] == i) return true;
    }
  return false;
}

}  // namespace

traced_index make_traced_index(const pointset& set, uint32_t k_used) {
  require_neighbours(set);
  const knn_table& t = set.table;
  if (k_used < 1) throw std::invalid_argument("k_used must be at least 1");
  k_used = std::min(k_used, stored_k(set));  // as traced_point_mask reads it
  traced_index index;
  index.k_used = k_used;
  const size_t n = set.points.size();
  index.morton = true;
  for (size_t i = 1; i < n && index.morton; ++i)
    index.morton = morton_code(set.points[i - 1].x, set.points[i - 1].y) <= morton_code(set.points[i].x, set.points[i].y);
  // Sides packed with their witnesses, so that one atomic min or max keeps both.
  std::vector<std::atomic<uint64_t>> sides(4 * n);
  for (size_t i = 0; i < n; ++i) {
    sides[4 * i].store(UINT64_MAX, std::memory_order_relaxed);
    sides[4 * i + 1].store(0, std::memory_order_relaxed);
    sides[4 * i + 2].store(UINT64_MAX, std::memory_order_relaxed);
    sides[4 * i + 3].store(0, std::memory_order_relaxed);
  }
  auto lower = [](std::atomic<uint64_t>& a, uint64_t v) {
    uint64_t cur = a.load(std::memory_order_relaxed);
    while (v < cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
    }
  };
  auto raise = [](std::atomic<uint64_t>& a, uint64_t v) {
    uint64_t cur = a.load(std::memory_order_relaxed);
    while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
    }
  };
  auto mark = [&](uint32_t i, uint32_t x, uint32_t y) {
    const uint64_t xy = uint64_t(x) << 32 | y, yx = uint64_t(y) << 32 | x;
    lower(sides[4 * size_t(i)], xy);
    raise(sides[4 * size_t(i) + 1], xy);
    lower(sides[4 * size_t(i) + 2], yx);
    raise(sides[4 * size_t(i) + 3], yx);
  };
  const uint32_t width = set.canvas_width();
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, set.canvas_height(), 8), [&](const tbb::blocked_range<uint32_t>& rows) {
    uint32_t found[max_knn];
    for (uint32_t y = rows.begin(); y < rows.end(); ++y)
      if (t.k != 0) {
        for (uint32_t j = 0; j < k_used; ++j)
          for (uint32_t x = 0; x < width; ++x) mark(t.entries[t.offset(uint64_t(y) * width + x, j)], x, y);
      } else {
        for (uint32_t x = 0; x < width; ++x) {
          cell_neighbours(set.cells, set.points, x, y, k_used, found);
          for (uint32_t j = 0; j < k_used; ++j) mark(found[j], x, y);
        }
      }
  });
  index.reaches.resize(n);
  float margin = 0;
  for (size_t i = 0; i < n; ++i) {
    traced_index::reach& r = index.reaches[i];
    r = {sides[4 * i].load(), sides[4 * i + 1].load(), sides[4 * i + 2].load(), sides[4 * i + 3].load()};
    if (r.min_x > r.max_x) continue;
    const point& p = set.points[i];
    margin = std::max({margin, p.x - float(r.min_x >> 32), float((r.max_x >> 32) + 1) - p.x,
                       p.y - float(r.min_y >> 32), float((r.max_y >> 32) + 1) - p.y});
  }
  index.margin = uint32_t(std::ceil(margin)) + 1;
  return index;
}

std::vector<uint32_t> traced_points(const pointset& set, const traced_index& index, gaze_point gaze) {
  require_neighbours(set);
  if (index.reaches.size() != set.points.size() || index.k_used < 1 || index.k_used > stored_k(set))
    throw std::invalid_argument("the traced-point index was not made for this set");
  if (!index.morton) return traced_points(set, gaze, index.k_used);
  const display_geometry& d = set.model.display;
  const canvas_offset o = offset_for_gaze(d, gaze);
  const pixel_rect screen{o.x, o.y, int64_t(o.x) + d.width, int64_t(o.y) + d.height};
  const int64_t m = index.margin;
  const pixel_rect near{screen.x0 - m, screen.y0 - m, screen.x1 + m, screen.y1 + m};
  // Runs [first, last) of traced points, ascending: quadtree cells of the canvas are
  // ranges of the Morton order; a cell on the screen is traced whole, one beyond the
  // margin not at all, and the points of the cells between are tested one by one.
  std::vector<std::pair<uint32_t, uint32_t>> runs;
  auto add = [&](uint32_t first, uint32_t last) {
    if (!runs.empty() && runs.back().second == first) runs.back().second = last;
    else runs.emplace_back(first, last);
  };
  const point* points = set.points.data();
  auto visit = [&](auto&& self, int64_t x0, int64_t y0, int64_t size, uint32_t a, uint32_t b) -> void {
    if (a == b) return;
    const pixel_rect cell{x0, y0, x0 + size, y0 + size};
    if (cell.within(screen)) return add(a, b);
    if (!cell.meets(near)) return;
    if (size <= 8 || b - a <= 16) {
      for (uint32_t i = a; i < b; ++i)
        if (on_screen(points[i], d, o) || read_on_screen(set, index, i, screen)) add(i, i + 1);
      return;
    }
    const int64_t h = size / 2;
    const int64_t cx[4] = {x0, x0 + h, x0, x0 + h}, cy[4] = {y0, y0, y0 + h, y0 + h};
    uint32_t start = a;
    for (int q = 0; q < 4; ++q) {
      uint32_t end = b;
      if (q < 3) {
        const uint64_t next = morton_code(float(cx[q + 1]), float(cy[q + 1]));
        end = uint32_t(std::partition_point(points + start, points + b, [&](const point& p) {
                         return morton_code(p.x, p.y) < next;
                       }) - points);
      }
      self(self, cx[q], cy[q], h, start, end);
      start = end;
    }
  };
  int64_t root = 1;
  while (root < int64_t(std::max(set.canvas_width(), set.canvas_height()))) root *= 2;
  visit(visit, 0, 0, root, 0, uint32_t(set.points.size()));
  // The runs written out in parallel, by blocks of the output.
  std::vector<size_t> starts(runs.size() + 1, 0);
  for (size_t r = 0; r < runs.size(); ++r) starts[r + 1] = starts[r] + (runs[r].second - runs[r].first);
  std::vector<uint32_t> out(starts.back());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, out.size(), 32768), [&](const tbb::blocked_range<size_t>& block) {
    size_t r = size_t(std::upper_bound(starts.begin(), starts.end(), block.begin()) - starts.begin()) - 1;
    for (size_t at = block.begin(); at < block.end(); ++r) {
      const size_t end = std::min(block.end(), starts[r + 1]);
      for (uint32_t i = runs[r].first + uint32_t(at - starts[r]); at < end; ++at, ++i) out[at] = i;
    }
  });
  return out;
}

traced_set count_traced_points(const pointset& set, gaze_point gaze, uint32_t k_used) {
  const std::vector<uint8_t> mask = traced_point_mask(set, gaze, k_used);
  const display_geometry& d = set.model.display;
  const canvas_offset o = offset_for_gaze(d, gaze);
  traced_set out;
  for (size_t i = 0; i < set.points.size(); ++i) {
    if (!mask[i]) continue;
    (on_screen(set.points[i], d, o) ? out.on_screen : out.referenced_off_screen)++;
  }
  return out;
}

void build_neighbours(pointset& set, const knn_params& knn, knn_storage storage) {
  if (storage == knn_storage::table) {
    set.table = build_knn_table(set.points, set.canvas_width(), set.canvas_height(), knn);
    set.cells = {};
  } else {
    knn_cells_params cp;
    cp.k = knn.k;
    set.cells = build_knn_cells(set.points, set.canvas_width(), set.canvas_height(), cp);
    set.table = {};
  }
}

std::vector<point> place_points(const spacing_model& model, const dart_params& darts, dart_stats* stats) {
  if (darts.sampler == point_sampler::poisson) return throw_darts(model, darts, stats);
  if (darts.fovea != fovea_layout::darts) throw std::invalid_argument("a grid fovea is for darts, not lattice samplers");
  const auto start = std::chrono::steady_clock::now();
  std::vector<point> points = lattice_points(model, darts.sampler);
  if (stats) {
    *stats = {};
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return points;
}

pointset generate_pointset(const spacing_model& model, const dart_params& darts, const knn_params& knn,
                           knn_storage storage) {
  pointset set;
  set.model = model;
  set.darts = darts;
  set.points = place_points(model, darts, &set.stats);
  const auto start = std::chrono::steady_clock::now();
  build_neighbours(set, knn, storage);
  set.knn_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
}

pointset throw_nested_pointset(const spacing_model& model, const std::vector<double>& scales, const dart_params& darts) {
  if (const std::string why = levels_problem(scales); !why.empty()) throw std::invalid_argument(why);
  if (darts.sampler != point_sampler::poisson) throw std::invalid_argument("a nested set is darts, not a lattice");
  pointset set;
  set.model = model;
  set.model.scale = scales.front();
  set.darts = darts;
  nested_points nested = throw_nested_darts(model, scales, darts, &set.stats);
  set.points = std::move(nested.points);
  set.level = std::move(nested.level);
  set.level_scales.assign(scales.rbegin(), scales.rend());  // coarsest first
  return set;
}

uint64_t coarsest_level_points(const pointset& set) {
  return set.level.empty() ? set.points.size() : uint64_t(std::count(set.level.begin(), set.level.end(), uint8_t(0)));
}

pointset generate_nested_pointset(const spacing_model& model, const std::vector<double>& scales, const dart_params& darts,
                                  const knn_params& knn, knn_storage storage) {
  pointset set = throw_nested_pointset(model, scales, darts);
  if (const uint64_t coarsest = coarsest_level_points(set); coarsest < knn.k)
    throw std::invalid_argument(fmt::format("k = {} exceeds the {} points of the coarsest level", knn.k, coarsest));
  const auto start = std::chrono::steady_clock::now();
  build_neighbours(set, knn, storage);
  set.knn_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
}

pointset uniform_pointset(const display_geometry& display, double fraction, const knn_params& knn,
                          knn_storage storage) {
  int m = -1;
  for (int i = 0; i <= 16; ++i)
    if (fraction == std::ldexp(1.0, -i)) m = i;
  if (m < 1) throw std::invalid_argument("a uniform set's fraction of the pixels must be 1/2, 1/4, 1/8, ... 1/65536");
  const int block = 1 << (m / 2);  // 2^j for fraction 4^-j or 2 x 4^-j
  const bool quincunx = m % 2 == 1;
  pointset set;
  set.model.display = display;
  const float spacing = float(block) * (quincunx ? std::sqrt(2.0f) : 1.0f);
  const int bx = int(set.canvas_width()) / block, by = int(set.canvas_height()) / block;
  for (int j = 0; j < by; ++j)
    for (int i = 0; i < bx; ++i)
      if (!quincunx || (i + j) % 2 == 0)
        set.points.push_back({float(i * block) + 0.5f * float(block), float(j * block) + 0.5f * float(block), spacing});
  sort_morton(set.points);
  set.stats.phase1_points = set.points.size();
  build_neighbours(set, knn, storage);
  return set;
}

}  // namespace fov
