#include "fov/reconstruct.h"

#include <cmath>
#include <limits>
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

constexpr uint32_t max_neighbours = 32;

}  // namespace

const char* method_name(method m) {
  switch (m) {
    case method::nn: return "nn";
    case method::shepard: return "shepard";
  }
  return "unknown";
}

bool parse_method(const std::string& name, method& out) {
  if (name == "nn") { out = method::nn; return true; }
  if (name == "shepard") { out = method::shepard; return true; }
  return false;
}

frame reconstruct(const pointset& set, const point_samples& samples, const reconstruct_params& params) {
  const knn_table& t = set.table;
  if (params.k < 1 || params.k > t.k)
    throw std::invalid_argument(fmt::format("k must lie in 1..{} (the set's k), got {}", t.k, params.k));
  if (samples.colour.size() != set.points.size()) throw std::invalid_argument("samples do not belong to this set");
  const int w = set.model.display.width, h = set.model.display.height;
  const canvas_offset o = samples.offset;
  frame out;
  out.width = w;
  out.height = h;
  out.rgb.resize(size_t(w) * h);
  out.depth.resize(size_t(w) * h);
  const uint32_t k = params.k;
  constexpr float infinity = std::numeric_limits<float>::infinity();
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
    double dist[max_neighbours], dist_hit[max_neighbours], depth[max_neighbours];
    rgbd value[max_neighbours];
    for (int sy = rows.begin(); sy < rows.end(); ++sy) {
      const uint64_t row = uint64_t(sy + o.y) * t.width + uint64_t(o.x);
      const double py = sy + o.y + 0.5;
      for (int sx = 0; sx < w; ++sx) {
        const size_t at = size_t(sy) * w + sx;
        if (params.how == method::nn) {
          const uint32_t i = t.entries[t.offset(row + sx, 0)];
          out.rgb[at] = samples.colour[i];
          out.depth[at] = samples.depth[i];
          continue;
        }
        const double px = sx + o.x + 0.5;
        uint32_t hits = 0;
        for (uint32_t j = 0; j < k; ++j) {
          const uint32_t i = t.entries[t.offset(row + sx, j)];
          const point& p = set.points[i];
          dist[j] = std::hypot(double(p.x) - px, double(p.y) - py);
          const glm::vec3& c = samples.colour[i];
          value[j] = {c.r, c.g, c.b};
          if (std::isfinite(samples.depth[i])) dist_hit[hits] = dist[j], depth[hits++] = samples.depth[i];
        }
        const rgbd c = shepard_weighted(dist, value, k, params.renka);
        out.rgb[at] = glm::vec3(float(c.r), float(c.g), float(c.b));
        out.depth[at] = hits ? float(shepard_weighted(dist_hit, depth, hits, params.renka)) : infinity;
      }
    }
  });
  return out;
}

}  // namespace fov
