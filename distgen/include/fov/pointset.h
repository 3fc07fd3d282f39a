// A foveated point set: Poisson-disc points on a 2W x 2H canvas whose centre is
// the gaze, stored in Morton order, plus the k nearest points of every canvas pixel.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <vector>

#include "fov/acuity.h"
#include "fov/labels.h"

namespace fov {

// One point of the set, in canvas pixels (pixel (i, j) covers [i, i+1) x [j, j+1)).
struct point {
  float x = 0, y = 0;
  float spacing = 0;  // p: the minimum distance that was enforced when it was accepted
};

// How the fovea is filled. The value is stored in point-set files, so never renumber.
enum class fovea_layout : uint32_t {
  darts = 0,  // Poisson-disc darts everywhere, as the thesis throws them
  grid = 1,   // one point at every canvas pixel centre where the model's spacing is at most
              // dart_params::grid_spacing (the thesis's "regular pixel density" of the fovea,
              // Sec. 8.2, made exact); darts fill the rest, none inside a grid pixel
};
inline constexpr std::pair<const char*, fovea_layout> fovea_layout_labels[] = {
    {"darts", fovea_layout::darts}, {"grid", fovea_layout::grid}};

// What places a set's points (docs/schemes.md). The value is stored in point-set files (version
// 4), so never renumber.
enum class point_sampler : uint32_t {
  poisson = 0,    // Poisson-disc darts at the acuity model's spacing (the thesis; dart_throwing.h)
  polar = 1,      // rings one sample pitch apart, each ring's samples a pitch apart (HVVR's pattern; lattice.h)
  log_polar = 2,  // VaFR's log-polar lattice: a ring at every unit of u(r) = integral of dr / pitch (lattice.h)
};
inline constexpr std::pair<const char*, point_sampler> point_sampler_labels[] = {
    {"poisson", point_sampler::poisson}, {"polar", point_sampler::polar}, {"log-polar", point_sampler::log_polar}};

// The grid spacings a set may have (dart_params::grid_spacing), pixels.
inline constexpr double min_grid_spacing = 0.5, max_grid_spacing = 4;
inline bool valid_grid_spacing(double p) { return p >= min_grid_spacing && p <= max_grid_spacing; }

// How the dart thrower runs and when it calls a region saturated.
struct dart_params {
  // What places the points: darts (all the fields below apply), or a ring lattice, which reads
  // none of them (it has no randomness: the seed is stored but changes nothing).
  point_sampler sampler = point_sampler::poisson;
  uint64_t seed = 1;
  // A tile is saturated after this many consecutive rejected darts.
  uint32_t saturation_rejections = 8000;
  // Phase 2 re-throws over this fraction of the screen size around the centre (thesis: 0.8).
  double central_fraction = 0.8;
  // Monte-Carlo probes used to estimate how much of the canvas is still free (0: skip).
  uint32_t free_area_probes = 1u << 20;
  fovea_layout fovea = fovea_layout::darts;
  // fovea_layout::grid: the largest model spacing (pixels) at which a pixel centre still gets
  // a grid point; 1 = wherever the model asks for points at most a pixel apart.
  // valid_grid_spacing: 0.5 .. 4.
  double grid_spacing = 1.0;
};

// What dart throwing did; all counts are exact, free_fraction is estimated.
struct dart_stats {
  uint64_t grid_points = 0;  // placed on pixel centres before any dart (fovea_layout::grid)
  uint64_t phase1_points = 0, phase2_points = 0;  // darts accepted in each phase
  uint64_t darts_thrown = 0;
  // Fraction of the canvas area where one more dart would still be accepted:
  // 0 means the set is maximal. Estimated from free_area_probes uniform probes.
  double free_fraction = 0;
  uint64_t free_probes_accepted = 0;
  double seconds = 0;  // wall time; not stored in files
};

// Bytes for large tables: 2 MiB-aligned, transparent huge pages requested (pointset.cpp).
void* allocate_table_bytes(size_t bytes);
void free_table_bytes(void* p);

// Storage for large tables: huge pages, and elements left uninitialised on resize
// (every entry is written right after). First-touch page faults dominated loading a
// 590 MB table here (docs/benchmarks.md).
template <class T>
struct table_allocator {
  using value_type = T;
  table_allocator() = default;
  template <class U>
  table_allocator(const table_allocator<U>&) {}
  T* allocate(size_t n) {
    if (n > (size_t(1) << 46) / sizeof(T)) throw std::bad_alloc();  // 64 TiB
    return static_cast<T*>(allocate_table_bytes(n * sizeof(T)));
  }
  void deallocate(T* p, size_t) { free_table_bytes(p); }
  template <class U>
  void construct(U* p) { ::new (static_cast<void*>(p)) U; }
  template <class U, class... A>
  void construct(U* p, A&&... a) { ::new (static_cast<void*>(p)) U(std::forward<A>(a)...); }
  template <class U>
  bool operator==(const table_allocator<U>&) const { return true; }
  template <class U>
  bool operator!=(const table_allocator<U>&) const { return false; }
};

// The k nearest points of every canvas pixel centre, nearest first (ties broken
// by the smaller point index). Stored in "grouped planes": neighbour ranks are
// cut into groups of `group` consecutive ranks; group g holds, for every pixel
// in row-major order, its ranks [g*group, min(k, (g+1)*group)) contiguously.
// group == 1 is one plane per rank, group == k is fully interleaved per pixel.
struct knn_table {
  uint32_t width = 0, height = 0;  // canvas size in pixels
  uint32_t k = 0;
  uint32_t group = 0;
  // Largest distance from a pixel centre to its k-th neighbour (derived, not stored in
  // files): a pixel farther than this from the screen edge reads only on-screen points.
  float max_radius = 0;
  // The same per rank: radius_by_rank[j] is the largest distance from a pixel centre to any
  // of its first j+1 neighbours (its (j+1)-th in a nearest-first table; derived; empty when
  // not computed). A reader of k' < k ranks needs only radius_by_rank[k' - 1] of border.
  std::vector<float> radius_by_rank;
  // The same per square tile of radius_tile x radius_tile canvas pixels (derived; empty
  // when not computed): radius_by_tile[(tile_y * tiles_x + tile_x) * k + j]. Near the
  // screen edge a pixel needs checking only where its tile's radius reaches past the edge;
  // the largest radii belong to the canvas corners, far from most screen edges.
  static constexpr uint32_t radius_tile = 32;
  std::vector<float> radius_by_tile;
  uint32_t radius_tiles_x() const { return (width + radius_tile - 1) / radius_tile; }
  uint32_t radius_tiles_y() const { return (height + radius_tile - 1) / radius_tile; }
  std::vector<uint32_t, table_allocator<uint32_t>> entries;  // width * height * k point indices

  uint64_t pixel_count() const { return uint64_t(width) * height; }
  // Offset of rank j (0 = nearest) of the pixel with row-major index `pixel`.
  uint64_t offset(uint64_t pixel, uint32_t j) const {
    const uint32_t g = j / group;
    const uint64_t width_g = std::min<uint64_t>(group, k - uint64_t(g) * group);
    return uint64_t(g) * group * pixel_count() + pixel * width_g + (j - g * group);
  }
  uint32_t at(uint32_t px, uint32_t py, uint32_t j) const {
    return entries[offset(uint64_t(py) * width + px, j)];
  }
};

// The k nearest points of any canvas pixel from storage that grows with the points: the
// candidates of an adaptive grid of cells (knn_cells.h says how they are built and read).
struct knn_cells {
  static constexpr uint32_t tile = 32;       // canvas pixels per tile side
  static constexpr uint32_t max_level = 5;   // cells of 1, 2, 4, ... 32 pixels

  uint32_t width = 0, height = 0;  // canvas size in pixels
  uint32_t k = 0;                  // the most neighbours a reader may ask for
  // Per tile, row-major: its first cell's index << 3 | its level.
  std::vector<uint32_t> tiles;
  // Per cell (a tile's cells row-major, tiles in order): the index of its first candidate
  // in `candidates`; one more entry closes the last cell.
  std::vector<uint32_t> cell_start;
  // Point indices; each cell's sorted by distance from the cell's centre (ties: smaller index).
  std::vector<uint32_t> candidates;

  uint32_t tiles_x() const { return (width + tile - 1) / tile; }
  uint32_t tiles_y() const { return (height + tile - 1) / tile; }
  uint64_t cell_count() const { return cell_start.empty() ? 0 : cell_start.size() - 1; }
  uint64_t bytes() const {
    return 4 * (uint64_t(tiles.size()) + cell_start.size() + candidates.size());
  }
  // Derived, not stored in files (the table's fields of the same names, as bounds):
  // radius_by_tile[t * k + j] bounds the distance from any pixel centre of tile t to its
  // first j + 1 neighbours (d_{j+1}(c) + delta over the tile's cells), radius_by_rank[j]
  // the same over all tiles, max_radius the k-th's.
  std::vector<float> radius_by_tile, radius_by_rank;
  float max_radius = 0;
  bool loaded() const { return k > 0 && tiles.size() == uint64_t(tiles_x()) * tiles_y() && !cell_start.empty(); }
};

// How a set keeps its neighbours in memory: the exact table (fast to read, 4 k bytes per
// canvas pixel) or the k-NN cells (ranked per pixel when read, memory that grows with the
// points). Both give every pixel the same neighbours.
enum class knn_storage : uint8_t { table, cells };
inline constexpr std::pair<const char*, knn_storage> knn_storage_labels[] = {{"table", knn_storage::table},
                                                                            {"cells", knn_storage::cells}};

// The most levels a nested set (fovgen --levels) may have.
inline constexpr uint32_t max_levels = 8;

struct pointset {
  spacing_model model;  // a nested set's: its finest level's scale
  dart_params darts;
  dart_stats stats;
  double knn_seconds = 0;  // wall time; not stored in files
  std::vector<point> points;  // Morton order
  // A nested set (fovgen --levels; dart_throwing.h): its levels' scales, coarsest (largest)
  // first, and each point's level, the first whose set holds it. Both empty for a set of one
  // level. The table or cells below are the finest level's: the set as a whole is a fixed
  // set at model.scale == level_scales.back(); nested.h makes each level a set of its own.
  std::vector<double> level_scales;
  std::vector<uint8_t> level;
  uint32_t level_count() const { return level_scales.empty() ? 1 : uint32_t(level_scales.size()); }
  bool nested() const { return !level_scales.empty(); }
  // The neighbours of every canvas pixel: the exact table, or (for sets too large for one)
  // the cells; a loaded set holds one of them.
  knn_table table;
  knn_cells cells;
  knn_storage storage() const { return table.k == 0 && cells.k != 0 ? knn_storage::cells : knn_storage::table; }

  uint32_t canvas_width() const { return 2u * uint32_t(model.display.width); }
  uint32_t canvas_height() const { return 2u * uint32_t(model.display.height); }
};

// The integer shift that puts the set's centre on the gaze: canvas = screen + offset.
// The gaze (screen pixels, continuous) is clamped to [0, W] x [0, H] and rounded
// half-up to a whole pixel, so offset = (W - round(gx), H - round(gy)).
struct canvas_offset {
  int x = 0, y = 0;
};
canvas_offset offset_for_gaze(const display_geometry& display, gaze_point gaze);

// True when a canvas point falls on the screen placed at `offset` (canvas = screen + offset).
inline bool on_screen(const point& p, const display_geometry& display, canvas_offset offset) {
  return p.x >= offset.x && p.x < offset.x + display.width && p.y >= offset.y && p.y < offset.y + display.height;
}

// True when the canvas pixel (px, py) holds a grid point: the layout is grid and the model's
// spacing at its centre is at most params.grid_spacing. The one rule the dart thrower places
// grid points by and every reader recognises them by (a disc around the canvas centre).
bool is_grid_pixel(const spacing_model& model, const dart_params& params, uint32_t px, uint32_t py);

// True when the canvas position (x, y) lies inside a grid pixel (is_grid_pixel of the pixel
// holding it). No dart lies there: the pixel's grid point gives its exact value, so a dart
// inside it would be traced without ever weighing in that pixel.
bool in_grid_pixel(const spacing_model& model, const dart_params& params, float x, float y);

// True when p is one of the set's grid points: it lies on the centre of a grid pixel. Grid
// points stand for whole pixels: the tracer casts a full-resolution pixel's rays for them.
bool is_grid_point(const pointset& set, const point& p);

// The layout in one word, as file names and tables write it: "darts", "grid" (the default
// grid spacing) or "grid-S" for another spacing S (e.g. "grid-1.10").
std::string fovea_label(const dart_params& params);

// The one file name of a set, from what fixes it: DISPLAY[-ACUITY][-SAMPLER]-sS[-FOVEA].fovset,
// where DISPLAY is display_name(model.display), ACUITY acuity_label(model.acuity) for any model
// but the thesis's CSF with its constants, SAMPLER the sampler's label but for poisson
// (fove-linear-mar-polar-s1.00.fovset), S the scale to 2 decimals and FOVEA fovea_label(darts)
// for a grid fovea (e.g. fove-s1.00.fovset, 640x720-v1-s1.75-grid.fovset,
// fove-linear-mar-s1.00.fovset); a nested set (level scales given, coarsest first) is
// DISPLAY[-ACUITY]-nS1-S2-...fovset, finest first as --levels lists them
// (fove-n0.70-1.00-3.00.fovset). Every tool that writes or looks for a set in a directory
// names it so.
std::string pointset_file_name(const spacing_model& model, const dart_params& darts,
                               const std::vector<double>& level_scales = {});

// The grid's radius: a distance from the canvas centre at which the model's spacing is at
// most params.grid_spacing, within 1e-9 px of the largest such (bisection; the spacing never
// shrinks with distance); -1 without a grid, or when even the centre's spacing exceeds it.
double grid_radius(const spacing_model& model, const dart_params& params);

// is_grid_point and in_grid_pixel for many points (the tracer asks for every traced point,
// the dart thrower for every dart, the loader for every point): the rim is found once, so
// only a point near it evaluates the model. Same answers, tested.
class grid_test {
 public:
  grid_test(const spacing_model& model, const dart_params& params);
  explicit grid_test(const pointset& set) : grid_test(set.model, set.darts) {}
  bool operator()(const point& p) const;            // is_grid_point
  bool in_grid_pixel(float x, float y) const;       // fov::in_grid_pixel

 private:
  spacing_model model_;
  dart_params params_;
  double inside2_ = -1, outside2_ = -1;  // squared distances: surely inside, surely outside
  double rim_ = -1;                      // beyond it no pixel is a grid pixel (-1: no grid)
};

// 64-bit Morton (Z-order) code of a canvas position, at 1/64-pixel resolution.
uint64_t morton_code(float x, float y);

// Number of pairs (i, j) closer than min(p_i, p_j): the spacing rule broken. Uses
// a grid; exact in double arithmetic on the stored float values.
uint64_t count_spacing_violations(const std::vector<point>& points, uint32_t canvas_width,
                                  uint32_t canvas_height);

// Throws std::invalid_argument unless the set's table or cells are loaded and match its
// canvas (a set read with load_params::table = false has neither).
void require_neighbours(const pointset& set);

// The most neighbours a reader of the set may ask for: its table's k, else its cells' k
// (known from the file's header even when neither was loaded; 0 for a set with neither).
uint32_t stored_k(const pointset& set);

// The k (1..stored_k) nearest points of canvas pixel (x, y)'s centre, nearest first (ties:
// the smaller index), from the table or the cells: the same answer from either.
void pixel_neighbours(const pointset& set, uint32_t x, uint32_t y, uint32_t k, uint32_t* out);

// Sets table.radius_by_tile, radius_by_rank (the largest distance from any pixel centre to
// its j-th neighbour: the maximum over tiles) and max_radius (the k-th, farthest stored).
void set_knn_radii(knn_table& table, const std::vector<point>& points);

// Points the renderer must trace for a gaze: every point on the screen plus every
// point any on-screen pixel reads among its first k_used neighbours.
struct traced_set {
  uint64_t on_screen = 0;
  uint64_t referenced_off_screen = 0;
  uint64_t total() const { return on_screen + referenced_off_screen; }
};
traced_set count_traced_points(const pointset& set, gaze_point gaze, uint32_t k_used);

// Marks (1) every point that must be traced for the gaze, as above; size = points.size().
std::vector<uint8_t> traced_point_mask(const pointset& set, gaze_point gaze, uint32_t k_used);

// The marked points' indices in ascending (Morton) order: what trace_points traces.
std::vector<uint32_t> traced_points(const pointset& set, gaze_point gaze, uint32_t k_used);

// What finds a gaze's traced points without reading the k-NN table every frame: for each
// point, the bounding box of the canvas pixels that read it among their first k_used
// neighbours, and on each side of the box one such pixel (a witness). An off-screen point
// is traced when its box meets the screen and a witness lies on it; only near the screen's
// corners, where no witness does, are the box's on-screen pixels read. Built once per set
// and k_used (one pass over the table's first k_used ranks); 32 bytes per point.
struct traced_index {
  uint32_t k_used = 0;
  // Sides of a point's box, each packed with its witness's other coordinate: min_x and
  // max_x are (x << 32 | y), min_y and max_y (y << 32 | x), of canvas pixels. A point no
  // pixel reads has min_x > max_x.
  struct reach {
    uint64_t min_x, max_x, min_y, max_y;
  };
  std::vector<reach> reaches;  // one per point
  uint32_t margin = 0;  // the farthest any pixel that reads a point lies from it, in whole pixels
  bool morton = false;  // the points are in Morton order (else traced_points scans the table)
};
traced_index make_traced_index(const pointset& set, uint32_t k_used);  // k_used above the table's k reads k

// The same list as traced_points(set, gaze, index.k_used), found with the index: the points'
// Morton order gives the on-screen points as ranges, and only points within the index's
// margin of the screen are tested one by one. `index` must be make_traced_index(set, k).
std::vector<uint32_t> traced_points(const pointset& set, const traced_index& index, gaze_point gaze);

}  // namespace fov
