#include "fov/reuse.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "fov/acuity.h"
#include "fov/colour.h"

namespace fov {

std::string validate(const reuse_params& p) {
  if (!(p.fovea_deg >= 0 && p.fovea_deg <= max_reuse_fovea_deg))
    return fmt::format("--reuse-fovea must lie in 0..{} degrees (got {})", max_reuse_fovea_deg, p.fovea_deg);
  if (!(p.threshold >= 0 && p.threshold <= 1)) return fmt::format("--reuse-threshold must lie in 0..1 (got {})", p.threshold);
  if (p.max_age < 1 || p.max_age > max_reuse_age)
    return fmt::format("--reuse-max-age must lie in 1..{} frames (got {})", max_reuse_age, p.max_age);
  if (p.budget > max_reuse_budget) return fmt::format("--reuse-budget must lie in 0..{} rays (got {})", max_reuse_budget, p.budget);
  if (!(p.view_deg >= 0 && p.view_deg <= max_reuse_view_deg))
    return fmt::format("--reuse-view must lie in 0..{} degrees (got {})", max_reuse_view_deg, p.view_deg);
  return "";
}

void reuse_history::reset(size_t n) {
  colour.assign(n, glm::vec3(0));
  where.assign(n, glm::vec3(0));
  depth_bias.assign(n, 0.0f);
  hits.assign(n, 0);
  kind.assign(n, seen::nothing);
  age.assign(n, 0);
  valid = false;
}

namespace {

constexpr float infinity = std::numeric_limits<float>::infinity();

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// TWFR's eccentricity confidence: 0 inside the fovea, 1 from three times it on.
double eccentricity_confidence(double e_deg, double fovea_deg) {
  if (fovea_deg <= 0) return 1;
  return smoothstep((e_deg - fovea_deg) / (2 * fovea_deg));
}

}  // namespace

reused_trace trace_reusing(const scene& s, const camera& cam, const pointset& set, const traced_index& index,
                           gaze_point gaze, const trace_params& params, const reuse_params& p, reuse_history& history) {
  if (const std::string why = validate(p); !why.empty()) throw std::invalid_argument(why);
  if (params.ray_floor != 0) throw std::invalid_argument("temporal reuse traces every point at spp rays: no ray floor");
  const display_geometry& disp = set.model.display;
  using clock = std::chrono::steady_clock;
  auto since = [](clock::time_point t) { return std::chrono::duration<double, std::milli>(clock::now() - t).count(); };
  clock::time_point t = clock::now();
  const point_probe probe = probe_points(s, cam, set, index, gaze, params);
  const double ms_probe = since(t);
  t = clock::now();
  const size_t n = set.points.size(), m = probe.points.size();
  const camera_frame now = make_frame(cam, disp.width, disp.height);
  spacing_model eye = set.model;  // the true eccentricity: the viewer's, not the set's scaled one
  eye.scale = 1;
  const uint32_t candidates = std::min<uint32_t>(std::min(params.k, stored_k(set)), 8);
  const float canvas_w = float(set.canvas_width()), canvas_h = float(set.canvas_height());
  std::vector<int64_t> source(m, -1);  // the history's point whose sample each listed point keeps
  std::vector<uint8_t> band(m);        // each listed point's eccentricity band
  std::vector<reuse_verdict> verdict(m, reuse_verdict::no_history);
  // Under a budget: each point's candidate below the threshold (-1: none within its disc, or
  // an edge), its confidence and eccentricity, which order the points the budget traces.
  const bool budgeted = p.budget > 0;
  std::vector<int64_t> fallback(budgeted ? m : 0, -1);
  std::vector<float> confidence(budgeted ? m : 0, 0.0f), eccentricity(budgeted ? m : 0, 0.0f);
  const bool usable = history.valid && history.colour.size() == n;
  // What deciding reads of each point, in one record (reuse_history::record), side by side:
  // its last-frame kind, age and luminance, where its sample lies (world: as stored; screen:
  // projected into this view once, not once for every point that tries it), and this frame's
  // probe distance for the edge test (+inf: a miss; NaN: not probed).
  using seen = reuse_history::seen;
  std::vector<reuse_history::record>& rec = history.spare.records;
  if (usable) {
    rec.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        reuse_history::record& c = rec[i];
        c.kind = history.kind[i];
        c.seen_now = std::numeric_limits<float>::quiet_NaN();
        if (c.kind != seen::hit && c.kind != seen::sloped && c.kind != seen::miss) continue;
        c.luminance = luminance(history.colour[i]);
        c.age = history.age[i];
        const glm::vec3& w = history.where[i];
        if (p.distance == reuse_distance::world) {
          c.at = w;
        } else {
          float z = 0;
          const glm::vec2 q = project(now, c.kind == seen::miss ? now.origin + w : w, &z);
          c.at = glm::vec3(q, z);
        }
      }
    });
    for (size_t j = 0; j < m; ++j) rec[probe.points[j]].seen_now = probe.distance[j];
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, m, 1024), [&](const tbb::blocked_range<size_t>& r) {
    uint32_t near[8];
    for (size_t j = r.begin(); j < r.end(); ++j) {
      const glm::vec2 at = probe.screen[j];
      const double e = eccentricity_deg(eye, std::hypot(at.x - gaze.x, at.y - gaze.y));
      band[j] = uint8_t(std::upper_bound(std::begin(reuse_band_edges_deg), std::end(reuse_band_edges_deg), e) -
                        std::begin(reuse_band_edges_deg));
      if (!usable) continue;
      reuse_verdict& why = verdict[j];
      const double ce = eccentricity_confidence(e, p.fovea_deg);
      why = reuse_verdict::eccentricity;
      if (!budgeted && (ce <= 0 || ce < p.threshold)) continue;
      why = reuse_verdict::off_canvas;
      const bool hit = probe.distance[j] != infinity;
      // Near an edge (a neighbour's probe met another surface: over 10 % nearer or farther, or
      // a hit beside a miss) the disc may hold what its centre does not see: traced.
      {
        const glm::vec2 here = canvas_position(disp, at, probe.offset, probe.mirror_x, probe.mirror_y);
        if (!(here.x >= 0 && here.x < canvas_w && here.y >= 0 && here.y < canvas_h)) continue;
        pixel_neighbours(set, uint32_t(here.x), uint32_t(here.y), candidates, near);
        bool edge = false;
        for (uint32_t k = 0; k < candidates && !edge; ++k) {
          const float other = rec[near[k]].seen_now;
          if (std::isnan(other)) continue;
          edge = hit ? !(std::fabs(other - probe.distance[j]) <= 0.1f * probe.distance[j]) : other != infinity;
        }
        if (edge) {
          why = reuse_verdict::edge_now;
          continue;
        }
      }
      float z = 0;
      const glm::vec2 q = project(history.view, hit ? probe.where[j] : history.view.origin + probe.where[j], &z);
      if (!(z > 0)) continue;
      const glm::vec2 then = canvas_position(disp, q, history.offset, history.mirror_x, history.mirror_y);
      if (!(then.x >= 0 && then.x < canvas_w && then.y >= 0 && then.y < canvas_h)) continue;
      pixel_neighbours(set, uint32_t(then.x), uint32_t(then.y), candidates, near);
      const seen want = hit ? seen::hit : seen::miss;
      const bool sloped_is_hit = hit && p.edges == reuse_edges::silhouettes;
      const float centre_depth = hit ? glm::dot(probe.where[j] - now.origin, now.forward) : 0.0f;
      int64_t best = -1;
      float best_distance = infinity, lo = infinity, hi = 0;
      bool edge_then = false;
      for (uint32_t c = 0; c < candidates; ++c) {
        const uint32_t i = near[c];
        const reuse_history::record& cand = rec[i];
        edge_then |= cand.kind == seen::mixed || (cand.kind == seen::sloped && p.edges == reuse_edges::strict);
        if (cand.kind != want && !(sloped_is_hit && cand.kind == seen::sloped)) continue;
        lo = std::min(lo, cand.luminance), hi = std::max(hi, cand.luminance);
        if (cand.age >= p.max_age) continue;
        // world: for hits the world distance, for misses the chord between the directions (the
        // angle, nearly); screen: the pixels between the point and the sample seen from here.
        float d = 0;
        if (p.distance == reuse_distance::world) {
          d = glm::distance(cand.at, probe.where[j]);
        } else {
          const float z = cand.at.z;
          if (!(z > 0) || (hit && !(std::fabs(z - centre_depth) <= 0.1f * centre_depth))) continue;
          d = glm::distance(glm::vec2(cand.at), at);
        }
        if (d < best_distance) best_distance = d, best = i;
      }
      if (best < 0 || edge_then) {
        why = edge_then ? reuse_verdict::edge_then : reuse_verdict::no_candidate;
        continue;
      }
      // The candidates' contrast (Michelson, of their luminances): a displaced sample shows
      // where the colour changes, not where it is flat.
      const double contrast = hi > 0 ? double(hi - lo) / double(hi + lo) : 0.0;
      // The disc's radius where its centre ray meets the world: on a plane facing the camera at
      // that depth (a hit), or as an angle (a miss; a pixel subtends less off the axis).
      const float cos_axis = glm::dot(glm::normalize(probe.where[j] - (hit ? now.origin : glm::vec3(0))), now.forward);
      const float disc = set.points[probe.points[j]].spacing * now.pixel_angle *
                         (hit ? probe.distance[j] * cos_axis : cos_axis * cos_axis);
      const float radius = p.distance == reuse_distance::world ? disc : set.points[probe.points[j]].spacing;
      double reprojection = std::max(0.0, 1.0 - double(best_distance) / double(radius));
      if (p.view_deg > 0 && hit) {  // how far the view onto the surface turned since
        const float cos_turn = glm::dot(glm::normalize(probe.where[j] - now.origin), glm::normalize(probe.where[j] - history.view.origin));
        const double turn = glm::degrees(std::acos(std::clamp(double(cos_turn), -1.0, 1.0)));
        reprojection *= std::max(0.0, 1.0 - turn / p.view_deg);
      }
      const double c = ce * (1 - contrast) * reprojection;
      why = reprojection > 0 ? reuse_verdict::below_threshold : reuse_verdict::out_of_reach;
      if (c > 0 && c >= p.threshold) {
        source[j] = best;
        why = reuse_verdict::kept;
      } else if (budgeted && reprojection > 0) {
        fallback[j] = best, confidence[j] = float(c), eccentricity[j] = float(e);
      }
    }
  });

  reused_trace out;
  reuse_report& rep = out.report;
  if (budgeted) {
    // Points without a candidate are traced whatever the budget; of those with one below the
    // threshold, the least confident (then the nearest the gaze) are traced while the budget
    // lasts and the rest keep their candidate.
    std::vector<uint32_t> below;
    uint64_t must = 0;
    for (size_t j = 0; j < m; ++j) {
      if (source[j] >= 0) continue;
      if (fallback[j] >= 0)
        below.push_back(uint32_t(j));
      else
        ++must;
    }
    std::stable_sort(below.begin(), below.end(), [&](uint32_t a, uint32_t b) {
      return confidence[a] != confidence[b] ? confidence[a] < confidence[b] : eccentricity[a] < eccentricity[b];
    });
    const uint64_t must_rays = must * params.spp;
    rep.budget_short = must_rays > p.budget;
    const uint64_t affordable = rep.budget_short ? 0 : (p.budget - must_rays) / params.spp;
    for (size_t q = std::min<uint64_t>(affordable, below.size()); q < below.size(); ++q) {
      source[below[q]] = fallback[below[q]];
      verdict[below[q]] = reuse_verdict::kept;
      ++rep.kept_for_budget;
    }
  }
  std::vector<uint32_t> to_trace;
  for (size_t j = 0; j < m; ++j)
    if (source[j] < 0) to_trace.push_back(probe.points[j]);
  rep.ms_probe = ms_probe, rep.ms_decide = since(t);
  t = clock::now();
  out.trace = trace_listed_points(s, cam, set, to_trace, gaze, params);
  rep.ms_trace = since(t);
  t = clock::now();
  point_samples& smp = out.trace.samples;
  // The next history is written over the arrays of the one before this (allocating them
  // afresh each frame, a few tens of MB, cost more than deciding: docs/reuse.md). Only the
  // kinds need clearing: a point's other entries are read only when its kind says it was seen.
  reuse_history next;
  {
    reuse_history::arrays& a = history.spare;
    next.colour.swap(a.colour), next.where.swap(a.where), next.depth_bias.swap(a.depth_bias);
    next.hits.swap(a.hits), next.kind.swap(a.kind), next.age.swap(a.age);
  }
  next.colour.resize(n), next.where.resize(n), next.depth_bias.resize(n), next.hits.resize(n), next.age.resize(n);
  next.kind.assign(n, reuse_history::seen::nothing);
  // Each listed point's sample (kept or traced) into the frame's samples and the next
  // history, side by side (each point writes only its own entries); then the counts, in order.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, m, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t j = r.begin(); j < r.end(); ++j) {
      const uint32_t pt = probe.points[j];
      if (source[j] >= 0) {
        const size_t i = size_t(source[j]);
        const bool hit = history.kind[i] == reuse_history::seen::hit || history.kind[i] == reuse_history::seen::sloped;
        smp.colour[pt] = history.colour[i];
        smp.hits[pt] = history.hits[i];
        smp.depth[pt] = hit ? glm::dot(history.where[i] - now.origin, now.forward) + history.depth_bias[i] : infinity;
        next.colour[pt] = history.colour[i], next.where[pt] = history.where[i], next.hits[pt] = history.hits[i];
        next.depth_bias[pt] = history.depth_bias[i];
        next.kind[pt] = history.kind[i];
        next.age[pt] = uint16_t(history.age[i] + 1);
      } else {
        const bool hit = probe.distance[j] != infinity;
        next.colour[pt] = smp.colour[pt], next.where[pt] = probe.where[j], next.hits[pt] = smp.hits[pt];
        next.depth_bias[pt] = 0, next.age[pt] = 0;
        // A sample is kept only where all its rays saw what its centre saw: all hit or all missed.
        // ... and, for a hit, its rays' mean depth lies within half its disc's world radius of its
        // centre's (a disc across a depth edge has all its rays hit, on two surfaces).
        const float centre_depth = glm::dot(probe.where[j] - now.origin, now.forward);
        const float bias = smp.depth[pt] - centre_depth;
        const float disc = hit ? set.points[pt].spacing * now.pixel_angle * centre_depth : 0;
        next.kind[pt] = reuse_history::seen::mixed;
        if (hit && smp.hits[pt] == params.spp) {
          next.kind[pt] = std::fabs(bias) <= 0.5f * disc ? reuse_history::seen::hit : reuse_history::seen::sloped;
          next.depth_bias[pt] = bias;
        }
        if (!hit && smp.hits[pt] == 0) next.kind[pt] = reuse_history::seen::miss;
      }
    }
  });
  for (size_t j = 0; j < m; ++j) {
    ++rep.points_by_band[band[j]];
    ++rep.by_verdict[size_t(verdict[j])];
    if (source[j] >= 0) {
      ++rep.reused_by_band[band[j]];
      out.kept.push_back(probe.points[j]);
      ++rep.reused;
    } else {
      ++rep.traced;
    }
  }
  rep.points = m;
  rep.probe_rays = probe.rays;
  rep.rays_traced = smp.rays;
  rep.rays_reused = rep.reused * uint64_t(params.spp);
  smp.traced = probe.points;
  smp.rays += probe.rays;
  out.trace.stats.cast.primary += probe.rays;
  next.view = now;
  next.offset = probe.offset;
  next.mirror_x = probe.mirror_x, next.mirror_y = probe.mirror_y;
  next.valid = true;
  {
    reuse_history::arrays& a = next.spare;
    a.colour = std::move(history.colour), a.where = std::move(history.where), a.depth_bias = std::move(history.depth_bias);
    a.hits = std::move(history.hits), a.kind = std::move(history.kind), a.age = std::move(history.age);
    a.records = std::move(history.spare.records);
  }
  history = std::move(next);
  rep.ms_history = since(t);
  return out;
}

}  // namespace fov
