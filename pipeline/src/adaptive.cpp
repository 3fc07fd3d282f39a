#include "fov/adaptive.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "fov/knn_cells.h"

namespace fov {

std::string validate(const adaptive_params& p) {
  if (!(p.threshold >= 0 && p.threshold <= max_adaptive_threshold))
    return fmt::format("--adaptive-threshold must lie in 0..{} (got {})", max_adaptive_threshold, p.threshold);
  if (!(p.depth_ratio >= 0 && p.depth_ratio <= max_depth_ratio))
    return fmt::format("--adaptive-depth must lie in 0..{} (got {})", max_depth_ratio, p.depth_ratio);
  return "";
}

double contrast_threshold(const acuity_params& a, double f_cpd, double eccentricity_deg) {
  return a.ct0 * std::exp(a.alpha * f_cpd * (eccentricity_deg + a.e2) / a.e2);
}

point_samples level_samples(const nested_levels& levels, uint32_t l, const point_samples& all) {
  const set_level& v = levels.levels.at(l);
  point_samples s;
  const size_t n = v.global.size();
  s.colour.resize(n);
  s.depth.resize(n);
  s.hits.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const uint32_t i = v.global[j];
    s.colour[j] = all.colour[i], s.depth[j] = all.depth[i], s.hits[j] = all.hits[i];
  }
  // The level's traced points: those of its points the frame traced (both lists ascend).
  size_t j = 0;
  for (uint32_t i : all.traced) {
    while (j < n && v.global[j] < i) ++j;
    if (j < n && v.global[j] == i) s.traced.push_back(uint32_t(j));
  }
  s.offset = all.offset;
  s.mirror_x = all.mirror_x, s.mirror_y = all.mirror_y;
  s.rays = all.rays;
  return s;
}

namespace {

struct block_state {
  uint32_t x0, y0, x1, y1;  // canvas rectangle (clipped to the screen's part)
  double eccentricity;      // degrees, of its pixel nearest the gaze
  uint8_t level = 0;
  uint8_t kept = 0;         // the previous frame's level where the view did not change
};

// The global indices of the points block b reads at level l (unordered; may repeat).
std::vector<uint32_t> block_points(const nested_levels& levels, uint32_t l, const block_state& b, uint32_t k) {
  const set_level& v = levels.levels[l];
  std::vector<uint32_t> local;
  level_rect_points(v, b.x0, b.y0, b.x1, b.y1, k, local);
  for (uint32_t& i : local) i = v.global[i];
  return local;
}

// The largest Michelson contrast of any channel between the samples, and whether their depths
// differ by more than depth_ratio of the nearest (a hit beside a miss always does).
struct block_contrast {
  double colour = 0;
  bool depth_edge = false;
};
block_contrast contrast_of(const std::vector<uint32_t>& points, const point_samples& s, double depth_ratio) {
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  float zmin = std::numeric_limits<float>::infinity(), zmax = 0;
  bool hit = false, miss = false;
  for (uint32_t i : points) {
    lo = glm::min(lo, s.colour[i]), hi = glm::max(hi, s.colour[i]);
    if (std::isfinite(s.depth[i])) {
      hit = true;
      zmin = std::min(zmin, s.depth[i]), zmax = std::max(zmax, s.depth[i]);
    } else {
      miss = true;
    }
  }
  block_contrast c;
  if (points.empty()) return c;
  for (int ch = 0; ch < 3; ++ch) {
    const double a = std::max(0.0f, lo[ch]), b = std::max(0.0f, hi[ch]);
    if (b > 0) c.colour = std::max(c.colour, (b - a) / (b + a));
  }
  if (depth_ratio > 0) c.depth_edge = (hit && miss) || (hit && zmax - zmin > depth_ratio * zmin);
  return c;
}

}  // namespace

adaptive_trace trace_adaptive(const scene& sc, const camera& cam, const nested_levels& levels, gaze_point gaze,
                              const trace_params& tp, const adaptive_params& p, const refinement_map* previous) {
  if (levels.levels.empty()) throw std::invalid_argument("trace_adaptive: no levels");
  if (const std::string why = validate(p); !why.empty()) throw std::invalid_argument(why);
  const pointset& finest = *levels.levels.back().set;
  const display_geometry& disp = finest.model.display;
  const int w = disp.width, h = disp.height;
  const uint32_t level_count = uint32_t(levels.levels.size());
  const uint32_t k = std::min(tp.k, stored_k(finest));
  // The placement trace_points uses (a mirrored pattern: the mirrored gaze's).
  const gaze_point placed{tp.mirror_x ? w - gaze.x : gaze.x, tp.mirror_y ? h - gaze.y : gaze.y};
  const canvas_offset o = offset_for_gaze(disp, placed);

  adaptive_trace out;
  refinement_map& map = out.map;
  map.offset = o;
  map.mirror_x = tp.mirror_x, map.mirror_y = tp.mirror_y;
  const uint32_t B = refinement_block;
  map.x0 = uint32_t(o.x) / B * B, map.y0 = uint32_t(o.y) / B * B;
  map.blocks_x = (uint32_t(o.x + w) - map.x0 + B - 1) / B;
  map.blocks_y = (uint32_t(o.y + h) - map.y0 + B - 1) / B;
  const size_t block_count = size_t(map.blocks_x) * map.blocks_y;
  const bool keep = previous && previous->offset.x == o.x && previous->offset.y == o.y &&
                    previous->level.size() == block_count;
  std::vector<block_state> blocks(block_count);
  spacing_model unit = finest.model;
  unit.scale = 1;  // true eccentricity
  for (uint32_t by = 0; by < map.blocks_y; ++by)
    for (uint32_t bx = 0; bx < map.blocks_x; ++bx) {
      block_state& b = blocks[size_t(by) * map.blocks_x + bx];
      b.x0 = std::max(uint32_t(o.x), map.x0 + bx * B), b.x1 = std::min(uint32_t(o.x + w), map.x0 + (bx + 1) * B);
      b.y0 = std::max(uint32_t(o.y), map.y0 + by * B), b.y1 = std::min(uint32_t(o.y + h), map.y0 + (by + 1) * B);
      // The canvas centre (W, H) is where the gaze lies.
      const double dx = std::max({0.0, double(b.x0) - w, double(w) - double(b.x1)});
      const double dy = std::max({0.0, double(b.y0) - h, double(h) - double(b.y1)});
      b.eccentricity = eccentricity_deg(unit, std::hypot(dx, dy));
      if (keep) b.kept = std::min<uint8_t>(previous->level[size_t(by) * map.blocks_x + bx], uint8_t(level_count - 1));
    }
  if (keep) out.report.blocks_kept = std::count_if(blocks.begin(), blocks.end(), [](const block_state& b) { return b.kept > 0; });

  // Rays a point casts (spp, or its ray rule under ray_floor), as trace_points counts them.
  const bool falling = tp.ray_floor > 0;
  const falloff_rule rule = falling ? point_ray_rule(finest, gaze, tp.spp, tp.ray_floor) : falloff_rule{};
  auto rays_of = [&](uint32_t i) -> uint64_t {
    if (!falling) return tp.spp;
    const point& q = finest.points[i];
    double x = double(q.x) - o.x, y = double(q.y) - o.y;
    if (tp.mirror_x) x = w - x;
    if (tp.mirror_y) y = h - y;
    return rule.rays_at(std::hypot(x - gaze.x, y - gaze.y));
  };

  out.report.rays_per_level.assign(level_count, 0);
  out.report.points_per_level.assign(level_count, 0);
  std::vector<uint8_t> scheduled(finest.points.size(), 0);  // traced or about to be
  std::vector<uint32_t> seen(p.budget > 0 ? finest.points.size() : 0, 0);  // (budgets) counted for the candidate numbered seen - 1
  point_samples& all = out.traced.samples;
  // The coarsest level's trace makes the set-sized arrays; finer levels trace into them.
  auto trace_new = [&](std::vector<uint32_t> list, uint32_t l) {
    std::sort(list.begin(), list.end());
    out.report.points_per_level[l] = list.size();
    if (all.colour.empty()) {
      out.traced = trace_listed_points(sc, cam, finest, std::move(list), gaze, tp);
      out.report.rays_per_level[l] = all.rays;
      return;
    }
    out.report.rays_per_level[l] = trace_more_points(sc, cam, finest, list, gaze, tp, out.traced);
  };

  // Level 0: every block.
  std::vector<std::vector<uint32_t>> needed(block_count);
  tbb::parallel_for(size_t(0), block_count, [&](size_t b) { needed[b] = block_points(levels, 0, blocks[b], k); });
  {
    std::vector<uint32_t> list;
    for (const auto& n : needed)
      for (uint32_t i : n)
        if (!scheduled[i]) scheduled[i] = 1, list.push_back(i);
    trace_new(std::move(list), 0);
  }
  uint64_t used = all.rays;
  out.report.budget_short = p.budget > 0 && used > p.budget;

  const acuity_params& acuity = finest.model.acuity;
  const double fd = display_nyquist_cpd(disp);
  for (uint32_t l = 0; l + 1 < level_count; ++l) {
    // Which blocks at level l would show more at level l + 1, most visible first.
    struct candidate {
      double priority;
      uint32_t block;
    };
    std::vector<candidate> wanted;
    for (uint32_t b = 0; b < block_count; ++b) {
      block_state& s = blocks[b];
      if (s.level != l) continue;
      if (s.kept > l) {
        wanted.push_back({std::numeric_limits<double>::infinity(), b});
        continue;
      }
      if (p.threshold == 0) {
        wanted.push_back({0, b});
        continue;
      }
      const block_contrast c = contrast_of(needed[b], all, p.depth_ratio);
      // What level l resolves at the block: its scale's cut-off, at most the display's.
      const double fc = cutoff_frequency_cpd(acuity, levels.levels[l].scale * s.eccentricity);
      const double ct = fc >= fd ? std::numeric_limits<double>::infinity() : contrast_threshold(acuity, fc, s.eccentricity);
      const double ratio = c.colour / (p.threshold * ct);
      if (ratio >= 1 || (c.depth_edge && fc < fd)) wanted.push_back({c.depth_edge ? std::max(ratio, 1.0) : ratio, b});
    }
    std::stable_sort(wanted.begin(), wanted.end(), [](const candidate& a, const candidate& b) { return a.priority > b.priority; });
    if (p.budget > 0) std::fill(seen.begin(), seen.end(), 0u);
    std::vector<std::vector<uint32_t>> next(wanted.size());
    tbb::parallel_for(size_t(0), wanted.size(),
                      [&](size_t j) { next[j] = block_points(levels, l + 1, blocks[wanted[j].block], k); });
    std::vector<uint32_t> list;
    for (size_t j = 0; j < wanted.size(); ++j) {
      if (p.budget > 0) {  // what the block would cost: each new point once (a list may repeat one)
        uint64_t cost = 0;
        for (uint32_t i : next[j])
          if (!scheduled[i] && seen[i] != j + 1) seen[i] = uint32_t(j + 1), cost += rays_of(i);
        if (used + cost > p.budget) {
          ++out.report.refinements_left_out;
          continue;
        }
        used += cost;
      }
      for (uint32_t i : next[j])
        if (!scheduled[i]) scheduled[i] = 1, list.push_back(i);
      const uint32_t b = wanted[j].block;
      blocks[b].level = uint8_t(l + 1);
      needed[b] = std::move(next[j]);
    }
    out.report.points_refined += list.size();
    trace_new(std::move(list), l + 1);
  }
  map.level.resize(block_count);
  out.report.blocks_per_level.assign(level_count, 0);
  for (size_t b = 0; b < block_count; ++b) map.level[b] = blocks[b].level, ++out.report.blocks_per_level[blocks[b].level];
  return out;
}

}  // namespace fov
