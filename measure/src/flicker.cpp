#include "fov/flicker.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <stdexcept>

#include <glm/gtc/constants.hpp>

#include "fov/metrics.h"

namespace fov {

camera path_camera(const camera& still, const flicker_params& f, uint32_t n) {
  const float yaw = glm::radians(f.yaw_deg_per_frame * float(n));
  const glm::vec3 right = glm::normalize(glm::cross(still.forward, still.up));
  camera c = still;
  c.forward = glm::normalize(still.forward * std::cos(yaw) + right * std::sin(yaw));
  c.position = still.position + right * (f.shift_per_frame * float(n));
  return c;
}

gaze_point path_gaze(gaze_point start, const display_geometry& d, const flicker_params& f, uint32_t n) {
  return {std::clamp(start.x + f.gaze_px_per_frame * n, 0.0, double(d.width)), start.y};
}

namespace {

const display_geometry& display_in_use(const renderer& r) {
  const pointset* set = r.current_set();
  if (!set) throw std::logic_error("the flicker path: no point set in use");
  return set->model.display;
}

}  // namespace

std::vector<frame> converged_path(renderer& r, const render_params& p, uint32_t spp, uint64_t seed,
                                  const flicker_params& f) {
  if (f.frames < 2) throw std::invalid_argument("the flicker path needs at least 2 frames");
  const display_geometry& d = display_in_use(r);
  const camera still = r.cam();
  render_params q = p;
  q.spp = spp, q.seed = seed, q.reference_sampler = pixel_sampler::sobol;
  std::vector<frame> out;
  for (uint32_t n = 0; n < f.frames; ++n) {
    if (n > 0 && f.yaw_deg_per_frame == 0 && f.shift_per_frame == 0) {  // a still camera: the same rays, the same frame
      out.push_back(out.back());
      continue;
    }
    r.cam() = path_camera(still, f, n);
    frame image = r.reference(d.width, d.height, q).image;
    image.depth = {};  // colour is all JOD reads
    out.push_back(std::move(image));
  }
  r.cam() = still;
  return out;
}

flicker_report measure_flicker(renderer& r, gaze_point start, const render_params& p, const flicker_params& f,
                               const std::vector<frame>& converged) {
  if (f.frames < 2) throw std::invalid_argument("flicker needs at least 2 frames");
  const display_geometry& d = display_in_use(r);
  if (!converged.empty() && converged.size() != f.frames)
    throw std::invalid_argument("measure_flicker: " + std::to_string(converged.size()) + " converged frames for a path of " +
                                std::to_string(f.frames));
  const camera still = r.cam();
  render_params raw = p, blended = p;
  raw.taa = false;
  blended.taa = true;
  r.reset_history();
  frame previous_raw, previous_taa, previous_ref;
  flicker_report out;
  std::vector<std::unique_ptr<fvvdp>> jod;  // raw, TAA[, full resolution]
  if (!converged.empty())
    for (int i = 0; i < (f.full_resolution ? 3 : 2); ++i) jod.push_back(std::make_unique<fvvdp>(d, f.fps, f.photometry));
  for (uint32_t n = 0; n < f.frames; ++n) {
    r.cam() = path_camera(still, f, n);
    const gaze_point g = path_gaze(start, d, f, n);
    frame_timing t;
    frame now, now_taa;  // copies: the renderer reuses its frame
    if (p.adaptive.enabled) {  // a nested set refined per frame: the same stages, its own
      const adaptive_trace refined = r.trace_refined(g, raw, t);
      now = r.reconstruct_refined(refined, g, raw, t);
      if (f.taa_own_rays) {
        frame_timing own;
        now_taa = r.reconstruct_refined(r.trace_refined(g, blended, own), g, blended, own);
      } else {
        now_taa = r.reconstruct_refined(refined, g, blended, t);
      }
    } else {
      const points_trace traced = r.trace(g, raw, t);
      now = r.reconstruct(traced.samples, g, raw, t);
      if (f.taa_own_rays) {
        frame_timing own;
        const points_trace jittered = r.trace(g, blended, own);
        now_taa = r.reconstruct(jittered.samples, g, blended, own);
      } else {
        now_taa = r.reconstruct(traced.samples, g, blended, t);
      }
    }
    frame now_ref = f.full_resolution ? r.reference(d.width, d.height, raw).image : frame{};
    if (n > 0) {
      out.raw += mean_luminance_change(now, previous_raw);
      out.taa += mean_luminance_change(now_taa, previous_taa);
      if (f.full_resolution) out.reference += mean_luminance_change(now_ref, previous_ref);
    }
    if (!jod.empty()) {
      jod[0]->add(now, converged[n], g);
      jod[1]->add(now_taa, converged[n], g);
      if (jod.size() > 2) jod[2]->add(now_ref, converged[n], g);
    }
    previous_raw = std::move(now), previous_taa = std::move(now_taa), previous_ref = std::move(now_ref);
  }
  const double pairs = double(f.frames - 1);
  out.raw /= pairs, out.taa /= pairs, out.reference /= pairs;
  if (!jod.empty()) out.has_jod = true, out.jod_raw = jod[0]->result(), out.jod_taa = jod[1]->result();
  if (jod.size() > 2) out.jod_full = jod[2]->result();
  if (!f.full_resolution) out.reference = NAN;
  r.cam() = still;
  r.reset_history();
  return out;
}

std::vector<double> reuse_path_report::trace_ratios() const {
  std::vector<double> ratio(trace_ms_full.size());
  for (size_t i = 0; i < ratio.size(); ++i) ratio[i] = trace_ms_reuse[i] / trace_ms_full[i];
  return ratio;
}

reuse_path_report measure_reuse(renderer& r, gaze_point start, const render_params& p, const flicker_params& f,
                                const std::vector<frame>& converged, uint32_t timing_repeats, bool time_full_resolution) {
  if (f.frames < 2) throw std::invalid_argument("the reuse path needs at least 2 frames");
  if (p.reuse.mode == reuse_mode::none) throw std::invalid_argument("measure_reuse: p.reuse.mode is none");
  if (p.adaptive.enabled) throw std::invalid_argument("measure_reuse: temporal reuse does not combine with adaptive refinement");
  const display_geometry& d = display_in_use(r);
  if (!converged.empty() && converged.size() != f.frames)
    throw std::invalid_argument("measure_reuse: " + std::to_string(converged.size()) + " converged frames for a path of " +
                                std::to_string(f.frames));
  const camera still = r.cam();
  reuse_path_report out;
  for (const bool reusing : {false, true}) {
    render_params q = p;
    if (!reusing) q.reuse.mode = reuse_mode::none;
    r.reset_history();
    r.reset_reuse();
    std::unique_ptr<fvvdp> jod;
    if (!converged.empty()) jod = std::make_unique<fvvdp>(d, f.fps, f.photometry);
    frame previous;
    double change = 0;
    for (uint32_t n = 0; n < f.frames; ++n) {
      r.cam() = path_camera(still, f, n);
      const gaze_point g = path_gaze(start, d, f, n);
      frame_timing t;
      const points_trace traced = r.trace(g, q, t);
      frame now = r.reconstruct(traced.samples, g, q, t);
      (reusing ? out.rays_reuse : out.rays_full).push_back(t.rays);
      (reusing ? out.cast_reuse : out.cast_full).push_back(t.cast.total());
      if (reusing) out.reuse.push_back(t.reuse);
      if (n > 0) change += mean_luminance_change(now, previous);
      if (jod) jod->add(now, converged[n], g);
      previous = std::move(now);
    }
    (reusing ? out.flicker_reuse : out.flicker_full) = change / double(f.frames - 1);
    if (jod) (reusing ? out.jod_reuse : out.jod_full) = jod->result();
  }
  out.has_jod = !converged.empty();
  // Timing, interleaved (each pass starts with the next trace of the three, so that none always
  // finds the caches warm): a full trace leaves the reuse history as it was (trace() reads and
  // writes it only when reusing), so one renderer times both, frame by frame.
  render_params full = p;
  full.reuse.mode = reuse_mode::none;
  const size_t jobs = time_full_resolution ? 3 : 2;
  for (uint32_t k = 0; k < timing_repeats; ++k) {
    r.reset_reuse();
    for (uint32_t n = 0; n < f.frames; ++n) {
      r.cam() = path_camera(still, f, n);
      const gaze_point g = path_gaze(start, d, f, n);
      frame_timing t[3];
      for (size_t j = 0; j < jobs; ++j) {
        const size_t job = (j + k) % jobs;
        if (job == 0) r.trace(g, full, t[0]);
        else if (job == 1) r.trace(g, p, t[1]);
        else r.reference(d.width, d.height, full, &t[2]);
      }
      if (n == 0) continue;
      out.trace_ms_full.push_back(t[0].trace_ms);
      out.trace_ms_reuse.push_back(t[1].trace_ms);
      if (time_full_resolution) out.trace_ms_full_resolution.push_back(t[2].trace_ms);
    }
  }
  r.cam() = still;
  r.reset_history();
  r.reset_reuse();
  return out;
}

fvvdp_result converged_path_floor(const std::vector<frame>& second, const std::vector<frame>& first, gaze_point start,
                                  const display_geometry& d, const flicker_params& f) {
  if (second.size() != first.size()) throw std::invalid_argument("converged_path_floor: paths of different lengths");
  fvvdp m(d, f.fps, f.photometry);
  for (uint32_t n = 0; n < first.size(); ++n) m.add(second[n], first[n], path_gaze(start, d, f, n));
  return m.result();
}

}  // namespace fov
