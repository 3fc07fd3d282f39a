#include "fov/reconstruct.h"

#include "fov/delaunay.h"
#include "fov/knn_cells.h"
#include "fov/weight_cache.h"

#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace fov {

namespace {

// Colour and depth as one value for the weighted sums (depth kept only where it is finite).
struct rgbd {
  double r = 0, g = 0, b = 0;
  rgbd operator+(const rgbd& o) const { return {r + o.r, g + o.g, b + o.b}; }
  rgbd operator*(double s) const { return {r * s, g * s, b * s}; }
};

}  // namespace

namespace {

double phi(double r, double c, rbf_kernel kernel) {
  return kernel == rbf_kernel::multiquadric ? std::sqrt(r * r + c * c) : std::exp(-(r * r) / (c * c));
}

// In-place LU with partial pivoting of the n x n row-major matrix m; false if singular.
bool lu_factor(double* m, int n, int* pivot) {
  double scale = 0;
  for (int i = 0; i < n * n; ++i) scale = std::max(scale, std::fabs(m[i]));
  for (int col = 0; col < n; ++col) {
    int best = col;
    for (int r = col + 1; r < n; ++r)
      if (std::fabs(m[r * n + col]) > std::fabs(m[best * n + col])) best = r;
    if (!(std::fabs(m[best * n + col]) > 1e-13 * scale)) return false;
    pivot[col] = best;
    if (best != col)
      for (int j = 0; j < n; ++j) std::swap(m[col * n + j], m[best * n + j]);
    for (int r = col + 1; r < n; ++r) {
      const double f = m[r * n + col] /= m[col * n + col];
      for (int j = col + 1; j < n; ++j) m[r * n + j] -= f * m[col * n + j];
    }
  }
  return true;
}

void lu_solve(const double* m, int n, const int* pivot, double* b) {
  for (int i = 0; i < n; ++i) {
    std::swap(b[i], b[pivot[i]]);
    for (int j = 0; j < i; ++j) b[i] -= m[i * n + j] * b[j];
  }
  for (int i = n - 1; i >= 0; --i) {
    for (int j = i + 1; j < n; ++j) b[i] -= m[i * n + j] * b[j];
    b[i] /= m[i * n + i];
  }
}

constexpr int max_system = 33;  // 32 neighbours + the constant term

// The distance from a pixel centre to a point, both on the canvas: coordinates of at most a
// few tens of thousands, whose squares cannot overflow or lose precision, so the plain
// formula serves where std::hypot's guard against both made it the reconstruction's costliest
// call.
inline double canvas_distance(double dx, double dy) { return std::sqrt(dx * dx + dy * dy); }

}  // namespace

bool rbf_weights(const double* px, const double* py, uint32_t k, double x, double y, double c, rbf_kernel kernel,
                 double* w, double* condition) {
  const int n = int(k) + 1;
  double m[max_system * max_system];
  int pivot[max_system];
  for (uint32_t i = 0; i < k; ++i) {
    for (uint32_t j = 0; j < k; ++j) m[i * n + j] = phi(std::hypot(px[i] - px[j], py[i] - py[j]), c, kernel);
    m[i * n + k] = m[k * n + i] = 1;
  }
  m[k * n + k] = 0;
  double norm = 0;  // 1-norm of the system, for the condition number
  if (condition)
    for (int j = 0; j < n; ++j) {
      double col = 0;
      for (int i = 0; i < n; ++i) col += std::fabs(m[i * n + j]);
      norm = std::max(norm, col);
    }
  if (!lu_factor(m, n, pivot)) return false;
  double b[max_system];
  for (uint32_t i = 0; i < k; ++i) b[i] = phi(std::hypot(x - px[i], y - py[i]), c, kernel);
  b[k] = 1;
  lu_solve(m, n, pivot, b);
  for (uint32_t i = 0; i < k; ++i) w[i] = b[i];
  if (condition) {  // ||M^-1||_1 from the inverse's columns
    double inverse_norm = 0;
    for (int j = 0; j < n; ++j) {
      double e[max_system] = {};
      e[j] = 1;
      lu_solve(m, n, pivot, e);
      double col = 0;
      for (int i = 0; i < n; ++i) col += std::fabs(e[i]);
      inverse_norm = std::max(inverse_norm, col);
    }
    *condition = norm * inverse_norm;
  }
  return true;
}

weight_stats& weight_stats::operator+=(const weight_stats& o) {
  pixels += o.pixels, fallbacks += o.fallbacks, sampled += o.sampled;
  near_duplicates += o.near_duplicates, singular += o.singular, weight_sum += o.weight_sum;
  outside_hull += o.outside_hull, beyond_k += o.beyond_k;
  worst_condition = std::max(worst_condition, o.worst_condition);
  worst_weight_sum = std::max(worst_weight_sum, o.worst_weight_sum);
  return *this;
}

std::string weight_fallback_warning(const weight_stats& s, method how) {
  if (s.fallbacks == 0) return "";
  if (delaunay_method(how))
    return fmt::format(
        "{} fell back to Shepard at {} of {} pixels weighed ({} outside the points' convex hull, {} weighing a point beyond "
        "their k nearest: raise --k)",
        method_name(how), s.fallbacks, s.pixels, s.outside_hull, s.beyond_k);
  return fmt::format(
      "RBF fell back to Shepard at {} of {} pixels weighed ({} with near-duplicate neighbours, {} singular systems, {} with "
      "weights whose absolute sum passed {})",
      s.fallbacks, s.pixels, s.near_duplicates, s.singular, s.weight_sum, rbf_max_weight_sum);
}

void shepard_weights(const double* h, uint32_t k, bool renka, double* w) {
  const double r = h[k - 1];
  double wsum = 0;
  for (uint32_t i = 0; i < k; ++i) {
    if (h[i] < on_point_px) {
      for (uint32_t j = 0; j < k; ++j) w[j] = j == i ? 1 : 0;
      return;
    }
    w[i] = h[i] >= r * (1 - shepard_tie) ? 0.0 : (r - h[i]) / (r * h[i]);
    if (renka) w[i] *= w[i];
    wsum += w[i];
  }
  for (uint32_t i = 0; i < k; ++i) w[i] = wsum > 0 ? w[i] / wsum : 1.0 / k;
}

void pixel_weights(const pointset& set, const reconstruct_params& params, uint32_t cx, uint32_t cy, double* w,
                   weight_stats* stats, const delaunay_weights* at) {
  const uint32_t k = params.k;
  uint32_t idx[max_knn];
  pixel_neighbours(set, cx, cy, k, idx);
  const double x = cx + 0.5, y = cy + 0.5;
  double xs[max_knn] = {}, ys[max_knn] = {}, dist[max_knn];
  double spacing = 0;  // RBF's c scales with the neighbours' mean spacing
  for (uint32_t j = 0; j < k; ++j) {
    const point& p = set.points[idx[j]];
    xs[j] = p.x, ys[j] = p.y, spacing += p.spacing;
    dist[j] = canvas_distance(double(p.x) - x, double(p.y) - y);
  }
  if (cached_weights_method(params.how)) {
    // A neighbour on the pixel centre (a grid point): the interpolant's value there is its
    // value, exactly, where a solved system would give it only to rounding.
    for (uint32_t j = 0; j < k; ++j)
      if (dist[j] < on_point_px) {
        if (stats) ++stats->pixels;
        for (uint32_t i = 0; i < k; ++i) w[i] = i == j ? 1 : 0;
        return;
      }
  }
  if (delaunay_method(params.how)) {
    if (!at) throw std::invalid_argument("pixel_weights: barycentric and natural need the pixel's Delaunay weights");
    if (stats) ++stats->pixels;
    if (at->where == delaunay_case::inside) {
      std::fill(w, w + k, 0.0);
      bool all_found = true;
      for (uint32_t n = 0; n < at->n && all_found; ++n) {
        uint32_t j = 0;
        while (j < k && idx[j] != at->index[n]) ++j;
        if (j == k) all_found = false;
        else w[j] += at->weight[n];
      }
      if (all_found) return;
      if (stats) ++stats->fallbacks, ++stats->beyond_k;
    } else if (at->where == delaunay_case::crowded) {
      if (stats) ++stats->fallbacks, ++stats->beyond_k;
    } else if (stats) {
      ++stats->fallbacks, ++stats->outside_hull;
    }
  } else if (params.how == method::rbf) {
    const bool sample = stats && (cy * 131 + cx) % 257 == 0;
    double condition = 0;
    if (stats) ++stats->pixels;
    bool duplicates = false;  // two neighbours all but on top of each other: a near-singular system
    for (uint32_t i = 0; i < k && !duplicates; ++i)
      for (uint32_t j = i + 1; j < k && !duplicates; ++j) {
        const double a = set.points[idx[i]].spacing, b = set.points[idx[j]].spacing;
        duplicates = std::hypot(xs[i] - xs[j], ys[i] - ys[j]) < rbf_duplicate_fraction * std::min(a, b);
      }
    if (duplicates) {
      if (stats) ++stats->fallbacks, ++stats->near_duplicates;
    } else if (!rbf_weights(xs, ys, k, x, y, params.shape * spacing / k, params.kernel, w, sample ? &condition : nullptr)) {
      if (stats) ++stats->fallbacks, ++stats->singular;
    } else {
      // The weights sum to 1, so the value lies within (sum |w| - 1) / 2 data ranges of the
      // data: past rbf_max_weight_sum the system amplifies rounding and noise, whatever its
      // pivots said.
      double absolute = 0;
      for (uint32_t j = 0; j < k; ++j) absolute += std::fabs(w[j]);
      if (absolute <= rbf_max_weight_sum) {
        if (stats) stats->worst_weight_sum = std::max(stats->worst_weight_sum, absolute);
        if (sample) ++stats->sampled, stats->worst_condition = std::max(stats->worst_condition, condition);
        return;
      }
      if (stats) ++stats->fallbacks, ++stats->weight_sum;
    }
  }
  shepard_weights(dist, k, params.renka, w);
}

void check_reconstruct_params(const reconstruct_params& params, uint32_t k_stored) {
  if (params.k < 1 || params.k > k_stored)
    throw std::invalid_argument(fmt::format("k must lie in 1..{} (the set's k), got {}", k_stored, params.k));
  if (params.how == method::rbf && !(params.shape > 0 && std::isfinite(params.shape)))
    throw std::invalid_argument("RBF shape must be positive");
}

void check_reconstruct_inputs(const pointset& set, const point_samples& samples, const reconstruct_params& params) {
  require_neighbours(set);
  check_reconstruct_params(params, stored_k(set));
  if (samples.colour.size() != set.points.size()) throw std::invalid_argument("samples do not belong to this set");
}

frame reconstruct(const pointset& set, const point_samples& samples, const reconstruct_params& params,
                  weight_stats* stats, weight_cache* cache) {
  frame out;
  reconstruct_into(set, samples, params, out, stats, cache);
  return out;
}

void reconstruct_into(const pointset& set, const point_samples& samples, const reconstruct_params& params, frame& out,
                      weight_stats* stats, weight_cache* cache, const level_mask* only) {
  check_reconstruct_inputs(set, samples, params);
  const bool weighted = cached_weights_method(params.how);
  std::unique_ptr<weight_cache> own;  // barycentric and natural without a cache: one for this call
  if (delaunay_method(params.how) && !cache) {
    own = std::make_unique<weight_cache>(set, params);
    cache = own.get();
  }
  if (weighted && cache) {
    if (!cache->serves(params)) throw std::invalid_argument("the weight cache was built for other parameters");
    cache->prepare(samples.offset);
    if (stats) *stats = cache->stats();
  }
  const knn_table& t = set.table;
  const bool table = t.k != 0;  // else the cells
  std::mutex stats_lock;
  const int w = set.model.display.width, h = set.model.display.height;
  const canvas_offset o = samples.offset;
  out.width = w;
  out.height = h;
  out.rays = 0;
  out.rgb.resize(size_t(w) * h);
  out.depth.resize(size_t(w) * h);
  const uint32_t k = params.k;
  constexpr float infinity = std::numeric_limits<float>::infinity();
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
    double dist[max_knn], dist_hit[max_knn], depth[max_knn], weight[max_knn];
    rgbd value[max_knn];
    weight_stats local;
    for (int sy = rows.begin(); sy < rows.end(); ++sy) {
      // A mirrored pattern: this screen pixel reads the table at the mirrored pixel.
      const int ty = samples.mirror_y ? h - 1 - sy : sy;
      const uint32_t cy = uint32_t(ty + o.y);
      const uint64_t row = uint64_t(cy) * t.width + uint64_t(o.x);  // table only
      const double py = cy + 0.5;
      uint32_t idx[max_knn];
      for (int sx = 0; sx < w; ++sx) {
        const size_t at = size_t(sy) * w + sx;
        const int tx = samples.mirror_x ? w - 1 - sx : sx;
        const uint32_t cx = uint32_t(tx + o.x);
        if (only && only->map->at(cx, cy) != only->level) continue;
        const uint32_t k_read = params.how == method::nn ? 1 : k;
        if (table)
          for (uint32_t j = 0; j < k_read; ++j) idx[j] = t.entries[t.offset(row + tx, j)];
        else
          cell_neighbours(set.cells, set.points, cx, cy, k_read, idx);
        if (params.how == method::nn) {
          out.rgb[at] = samples.colour[idx[0]];
          out.depth[at] = samples.depth[idx[0]];
          continue;
        }
        const double px = cx + 0.5;
        uint32_t hits = 0;
        int64_t on_point = -1;  // a neighbour on the pixel centre (a grid point): its index
        for (uint32_t j = 0; j < k; ++j) {
          const uint32_t i = idx[j];
          const point& p = set.points[i];
          dist[j] = canvas_distance(double(p.x) - px, double(p.y) - py);
          if (dist[j] < on_point_px && on_point < 0) on_point = i;
          const glm::vec3& c = samples.colour[i];
          value[j] = {c.r, c.g, c.b};
          if (std::isfinite(samples.depth[i])) dist_hit[hits] = dist[j], depth[hits++] = samples.depth[i];
        }
        rgbd c;
        if (weighted && cache) {
          const float* cached = cache->weights(cx, cy);
          for (uint32_t j = 0; j < k; ++j)
            if (cached[j] != 0) c = c + value[j] * double(cached[j]);
        } else if (weighted) {  // RBF solved per pixel
          pixel_weights(set, params, cx, cy, weight, stats ? &local : nullptr);
          for (uint32_t j = 0; j < k; ++j)
            if (weight[j] != 0) c = c + value[j] * weight[j];
        } else {
          c = shepard_weighted(dist, value, k, params.renka);
        }
        out.rgb[at] = glm::vec3(float(c.r), float(c.g), float(c.b));
        // On a point (a grid point): its depth, a miss included, as its colour is its own.
        out.depth[at] = on_point >= 0 ? samples.depth[size_t(on_point)]
                        : hits        ? float(shepard_weighted(dist_hit, depth, hits, params.renka))
                                      : infinity;
      }
    }
    if (stats && weighted && !cache) {
      std::lock_guard<std::mutex> guard(stats_lock);
      *stats += local;
    }
  });
}

}  // namespace fov
