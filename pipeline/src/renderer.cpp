#include "fov/renderer.h"

#include "fov/random.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "fov/weight_cache.h"

namespace fov {

namespace {

using clock_type = std::chrono::steady_clock;
double ms_since(clock_type::time_point t) {
  return std::chrono::duration<double, std::milli>(clock_type::now() - t).count();
}

// The settings a traced frame depends on (besides gaze, camera and set).
bool same_trace(const render_params& a, const render_params& b) {
  return a.spp == b.spp && a.seed == b.seed && a.shadows == b.shadows && a.footprint == b.footprint &&
         a.reconstruct.k == b.reconstruct.k && a.taa == b.taa && a.pattern == b.pattern && a.exposure_ev == b.exposure_ev && a.disc_sampler == b.disc_sampler &&
         a.sun_direction == b.sun_direction && a.sun_irradiance == b.sun_irradiance &&
         a.reference_sampler == b.reference_sampler && a.ray_floor == b.ray_floor && a.method == b.method &&
         a.bounces == b.bounces && a.rolling.order == b.rolling.order &&
         a.rolling.frame_period_ms == b.rolling.frame_period_ms && a.rolling.path == b.rolling.path &&
         a.rolling.start_ms == b.rolling.start_ms && a.rolling.stereo == b.rolling.stereo &&
         a.rolling.right_eye == b.rolling.right_eye && a.rolling.ipd_mm == b.rolling.ipd_mm && a.reuse.mode == b.reuse.mode &&
         a.reuse.fovea_deg == b.reuse.fovea_deg && a.reuse.threshold == b.reuse.threshold &&
         a.reuse.max_age == b.reuse.max_age && a.reuse.budget == b.reuse.budget && a.reuse.view_deg == b.reuse.view_deg &&
         a.reuse.edges == b.reuse.edges && a.reuse.distance == b.reuse.distance;
}

// The tracing half of the params, without a frame's pattern.
trace_params base_trace(const render_params& p) {
  trace_params tp;
  tp.spp = p.spp;
  tp.seed = p.seed;
  tp.shadows = p.shadows;
  tp.footprint = p.footprint;
  tp.sampler = p.reference_sampler;
  tp.disc_sampler = p.disc_sampler;
  tp.exposure_ev = p.exposure_ev;
  tp.method = p.method;
  tp.bounces = p.bounces;
  if (p.sun_direction || p.sun_irradiance) {
    light sun;
    if (p.sun_direction) sun.direction = glm::normalize(*p.sun_direction);
    if (p.sun_irradiance) sun.colour = *p.sun_irradiance;
    tp.sun = sun;
  }
  tp.k = p.reconstruct.k;
  tp.ray_floor = p.ray_floor;
  return tp;
}

}  // namespace

std::string validate(const render_params& p, const pointset* set) {
  if (p.spp < 1 || p.spp > max_spp) return fmt::format("--spp must lie in 1..{} (got {})", max_spp, p.spp);
  if (p.ray_floor > p.spp)
    return fmt::format("--ray-floor must lie in 1..--spp = {} (got {}): rays fall from --spp at the gaze", p.spp, p.ray_floor);
  const uint32_t k_max = set ? stored_k(*set) : max_knn;
  if (p.reconstruct.k < 1 || p.reconstruct.k > k_max)
    return fmt::format("--k must lie in 1..{}{} (got {})", k_max, set ? " (the set's k)" : "", p.reconstruct.k);
  if (!(p.reconstruct.shape > 0 && std::isfinite(p.reconstruct.shape)))
    return fmt::format("--rbf-shape must be positive (got {})", p.reconstruct.shape);
  if (!(std::fabs(p.exposure_ev) <= 20)) return fmt::format("--exposure must lie in -20..20 EV (got {})", p.exposure_ev);
  if (p.bounces > max_bounces) return fmt::format("--bounces must lie in 0..{} (got {})", max_bounces, p.bounces);
  if (p.sun_direction && !(glm::length(*p.sun_direction) > 1e-6f && std::isfinite(glm::length(*p.sun_direction))))
    return "--sun-dir must be a finite, non-zero direction";
  if (p.sun_irradiance && !(std::isfinite(glm::length(*p.sun_irradiance)) && glm::all(glm::greaterThanEqual(*p.sun_irradiance, glm::vec3(0))) &&
                            glm::all(glm::lessThanEqual(*p.sun_irradiance, glm::vec3(1e6f)))))
    return "--sun-irradiance must be finite, non-negative and at most 1e6 per channel";
  if (const std::string why = validate(p.adaptive); !why.empty()) return why;
  if (const std::string why = validate(p.rolling); !why.empty()) return why;
  if (const std::string why = validate(p.reuse); !why.empty()) return why;
  if (const std::string why = validate(p.stereo); !why.empty()) return why;
  const std::string reuse = std::string("--reuse ") + label_of(reuse_mode_labels, p.reuse.mode);
  if (p.reuse.mode != reuse_mode::none && p.adaptive.enabled) return reuse + " does not combine with --adaptive";
  if (p.reuse.mode != reuse_mode::none && p.rolling.order != scanout::global)
    return reuse + " does not combine with --rolling yet";
  if (p.reuse.mode != reuse_mode::none && p.ray_floor > 0)
    return reuse + " traces every point at --spp rays: drop --ray-floor";
  if (p.reuse.mode == reuse_mode::eyes && !p.stereo.enabled) return "--reuse eyes needs --stereo (two eyes)";
  if (p.adaptive.enabled && set && !set->nested())
    return "--adaptive needs a nested set (fovgen --levels); this set has one level";
  if (p.weight_caches < 1 || p.weight_caches > cl_reconstructor::max_weight_caches)
    return fmt::format("weight caches must lie in 1..{} (got {})", cl_reconstructor::max_weight_caches, p.weight_caches);
  if (!(p.temporal.alpha > 0 && p.temporal.alpha <= 1))
    return fmt::format("TAA alpha must lie in (0, 1] (got {})", p.temporal.alpha);
  return validate(p.view);
}

std::pair<uint64_t, uint64_t> converged_seeds(uint64_t seed) {
  return {stream_seed(seed, 0x636f6e7665726765ull, 0), stream_seed(seed, 0x636f6e7665726765ull, 1)};
}

trace_params renderer::frame_trace_params(const render_params& p, uint64_t n) {
  trace_params tp = base_trace(p);
  if (p.taa && p.pattern == ray_pattern::reseed) tp.seed = p.seed + n;
  if (p.taa && p.pattern == ray_pattern::mirror) tp.mirror_x = (n & 1) != 0, tp.mirror_y = (n & 2) != 0;
  return tp;
}

trace_params renderer::with_lines(trace_params tp, const render_params& p, int width, int height) const {
  tp.lines = rolling_cameras(p.rolling, cam_, width, height);
  return tp;
}

trace_params renderer::point_trace_params(const render_params& p, uint64_t n) const {
  const display_geometry& disp = set_->model.display;
  return with_lines(frame_trace_params(p, n), p, disp.width, disp.height);
}

renderer::renderer(std::shared_ptr<const scene> s, const render_params& p)
    : scene_(std::move(s)), cam_(setup_camera(*scene_, p.view)), device_kind_(p.device), weight_caches_(p.weight_caches) {
  if (p.rolling.path) cam_ = p.rolling.path->at(p.rolling.start_ms, cam_);
}

renderer::~renderer() = default;

void renderer::use_pointset(std::shared_ptr<const pointset> set) {
  if (set == set_) return;
  pending_.reset();
  device_.reset();  // holds a reference to the old set
  set_ = std::move(set);
  index_.reset();
  reuse_.clear();
  const auto t0 = clock_type::now();
  device_ = std::make_unique<cl_reconstructor>(*set_, device_kind_, weight_caches_);
  device_setup_ms_ = ms_since(t0);
  levels_.reset();
  level_devices_.clear();
  last_map_.reset();
  levels_setup_ms_ = 0;
  if (set_->nested()) {
    const auto t1 = clock_type::now();
    levels_ = std::make_shared<const nested_levels>(make_levels(set_));
    for (size_t l = 0; l + 1 < levels_->levels.size(); ++l)
      level_devices_.push_back(std::make_unique<cl_reconstructor>(*levels_->levels[l].set, device_kind_, weight_caches_));
    levels_setup_ms_ = ms_since(t1);
  }
  reset_history();
}

void renderer::require_set() const {
  if (!set_) throw std::logic_error("renderer: no point set in use (use_pointset)");
}

const std::string& renderer::device() const {
  static const std::string cpp = "C++ (TBB)";
  return device_ ? device_->device() : cpp;
}

bool renderer::on_device() const { return device_ && device_->available(); }

std::string renderer::device_problem() const {
  if (!device_ || device_kind_ == reconstruct_device::cpp || device_->available()) return "";
  return device_->reason();
}

std::string renderer::device_warning() const {
  const std::string problem = device_problem();
  return problem.empty() ? "" : "warning: " + problem + "; using the C++ path";
}

std::shared_ptr<const traced_index> renderer::index_for(const trace_params& tp) {
  const uint32_t k = std::min(tp.k, stored_k(*set_));
  if (!index_ || index_->k_used != k) index_ = std::make_shared<const traced_index>(make_traced_index(*set_, k));
  return index_;
}

points_trace renderer::trace(gaze_point gaze, const render_params& p, frame_timing& t) {
  require_set();
  return trace_frame(gaze, p, frames_traced_++, t);
}

points_trace renderer::trace_frame(gaze_point gaze, const render_params& p, uint64_t n, frame_timing& t,
                                   const reuse_history* other) {
  const trace_params tp = point_trace_params(p, n);
  const std::shared_ptr<const traced_index> index = index_for(tp);
  const auto t0 = clock_type::now();
  points_trace out;
  t.reused = p.reuse.mode == reuse_mode::temporal || other;
  if (t.reused) {
    // Another view's samples (of this instant: age 0), or the earlier frames' own.
    reuse_params rp = p.reuse;
    reuse_history copy;
    reuse_history* from = &reuse_;
    if (other) {
      rp.max_age = max_reuse_age;
      copy = *other;
      from = &copy;
    } else {
      if (!same_trace(reuse_params_, p)) reuse_.clear();  // samples of other settings hold nothing now
      reuse_params_ = p;
    }
    reused_trace r = trace_reusing(*scene_, cam_, *set_, *index, gaze, tp, rp, *from);
    out = std::move(r.trace);
    t.reuse = r.report;
  } else {
    out = trace_points(*scene_, cam_, *set_, *index, gaze, tp);
  }
  t.trace_ms = ms_since(t0);
  t.traced_ahead = false;
  t.trace_wait_ms = 0;
  t.rays = out.samples.rays;
  t.cast = out.stats.cast;
  t.points_traced = t.reused ? t.reuse.traced : out.samples.traced.size();
  return out;
}

const frame& renderer::reconstruct(const point_samples& samples, gaze_point gaze, const render_params& p,
                                   frame_timing& t) {
  require_set();
  const auto t0 = clock_type::now();
  reconstruct_result r;
  t.taa_ms = 0;
  if (p.taa && device_->available()) {
    // Reconstruction and TAA on the device, the frame kept there in between; TAA's share
    // is its kernel's time.
    r = device_->run_taa(samples, p.reconstruct, taa_, cam_, gaze, p.temporal, frame_);
    t.taa_ms = r.taa_kernel_ms;
    t.reconstruct_ms = ms_since(t0) - t.taa_ms;
  } else {
    r = device_->run(samples, p.reconstruct, frame_);
    t.reconstruct_ms = ms_since(t0);
    if (p.taa) {
      const auto t1 = clock_type::now();
      frame_ = taa_resolve(taa_, frame_, cam_, set_->model.display, gaze, p.temporal);
      t.taa_ms = ms_since(t1);
    }
  }
  t.on_device = r.on_device;
  t.weights = r.weights;
  return frame_;
}

void renderer::begin_trace(gaze_point gaze, const camera& view, const render_params& p) {
  require_set();
  pending_.reset();  // waits for one still running
  if (p.adaptive.enabled) return;  // an adaptive frame chooses its points from its own samples: traced in foveated()
  if (p.reuse.mode != reuse_mode::none) return;  // a reusing frame reads the last one's samples: traced in foveated()
  const trace_params tp = point_trace_params(p, frames_traced_++);
  auto job = [scn = scene_, set = set_, index = index_for(tp), view, gaze, tp] {
    const auto t0 = clock_type::now();
    points_trace out = trace_points(*scn, view, *set, *index, gaze, tp);
    return std::make_pair(std::move(out), ms_since(t0));
  };
  pending_ = pending_trace{gaze, view, p, set_, std::async(std::launch::async, std::move(job))};
}

adaptive_trace renderer::trace_refined_frame(gaze_point gaze, const render_params& p, uint64_t n, frame_timing& t) {
  if (!levels_) throw std::invalid_argument("--adaptive needs a nested set (fovgen --levels); this set has one level");
  if (const std::string why = validate(p.adaptive); !why.empty()) throw std::invalid_argument(why);
  const trace_params tp = point_trace_params(p, n);
  const bool same = last_map_ && same_view(last_map_camera_, cam_) && last_map_params_.threshold == p.adaptive.threshold &&
                    last_map_params_.depth_ratio == p.adaptive.depth_ratio && last_map_params_.budget == p.adaptive.budget;
  const auto t0 = clock_type::now();
  adaptive_trace a = trace_adaptive(*scene_, cam_, *levels_, gaze, tp, p.adaptive, same ? &*last_map_ : nullptr);
  t.trace_ms = ms_since(t0);
  t.traced_ahead = false;
  t.trace_wait_ms = 0;
  t.rays = a.traced.samples.rays;
  t.cast = a.traced.stats.cast;
  t.points_traced = a.traced.samples.traced.size();
  t.adaptive = true;
  t.refinement = a.report;
  last_map_ = a.map;
  last_map_camera_ = cam_;
  last_map_params_ = p.adaptive;
  return a;
}

adaptive_trace renderer::trace_refined(gaze_point gaze, const render_params& p, frame_timing& t) {
  require_set();
  pending_.reset();
  return trace_refined_frame(gaze, p, frames_traced_++, t);
}

const frame& renderer::reconstruct_refined(const adaptive_trace& a, gaze_point gaze, const render_params& p, frame_timing& t) {
  require_set();
  if (!levels_) throw std::invalid_argument("--adaptive needs a nested set (fovgen --levels); this set has one level");
  const auto t1 = clock_type::now();
  const point_samples& all = a.traced.samples;
  const uint32_t levels = uint32_t(levels_->levels.size());
  if (all.colour.size() != set_->points.size() || a.report.blocks_per_level.size() != levels)
    throw std::invalid_argument("reconstruct_refined: the refined trace belongs to another set");
  const display_geometry& disp = set_->model.display;
  const int w = disp.width, h = disp.height;
  reconstruct_result r;
  bool first = true;
  for (uint32_t l = 0; l < levels; ++l) {
    if (a.report.blocks_per_level[l] == 0) continue;
    const bool finest = l + 1 == levels;
    cl_reconstructor& dev = finest ? *device_ : *level_devices_[l];
    const level_mask only{&a.map, uint8_t(l)};
    // Each level rebuilds its own blocks' pixels alone; the first fills the frame, the others
    // are copied over it.
    frame& into = first ? frame_ : level_frame_;
    const reconstruct_result rl = finest ? dev.run(all, p.reconstruct, into, &only)
                                         : dev.run(level_samples(*levels_, l, all), p.reconstruct, into, &only);
    r.on_device = rl.on_device;
    r.weights += rl.weights;
    if (first) {
      first = false;
      continue;
    }
    tbb::parallel_for(0, h, [&](int sy) {
      for (int sx = 0; sx < w; ++sx) {
        uint32_t cx, cy;
        screen_to_canvas(all, w, h, sx, sy, cx, cy);
        if (a.map.at(cx, cy) != l) continue;
        const size_t at = size_t(sy) * w + sx;
        frame_.rgb[at] = level_frame_.rgb[at], frame_.depth[at] = level_frame_.depth[at];
      }
    });
  }
  frame_.rays = all.rays;
  t.reconstruct_ms = ms_since(t1);
  t.on_device = r.on_device;
  t.weights = r.weights;
  t.taa_ms = 0;
  if (p.taa) {
    const auto t2 = clock_type::now();
    frame_ = taa_resolve(taa_, frame_, cam_, disp, gaze, p.temporal);
    t.taa_ms = ms_since(t2);
  }
  return frame_;
}

const frame& renderer::adaptive_frame(gaze_point gaze, const render_params& p, uint64_t n, frame_timing& t) {
  const adaptive_trace a = trace_refined_frame(gaze, p, n, t);
  if (!p.taa) reset_history();
  return reconstruct_refined(a, gaze, p, t);
}

const frame& renderer::foveated(gaze_point gaze, const render_params& p, frame_timing* timing) {
  require_set();
  frame_timing t;
  if (p.adaptive.enabled) {
    pending_.reset();
    adaptive_frame(gaze, p, frames_traced_++, t);
    last_samples_ = {};
    if (timing) *timing = t;
    return frame_;
  }
  std::optional<points_trace> traced;
  if (pending_) {
    const auto t0 = clock_type::now();
    const bool ahead = pending_->gaze == gaze && same_view(pending_->view, cam_) && pending_->set == set_ &&
                       same_trace(pending_->params, p);
    auto [result, ms] = pending_->result.get();  // rethrows what the trace threw
    pending_.reset();
    if (ahead) {
      t.traced_ahead = true;
      t.trace_ms = ms;
      t.trace_wait_ms = ms_since(t0);
      t.rays = result.samples.rays;
      t.cast = result.stats.cast;
      t.points_traced = result.samples.traced.size();
      traced = std::move(result);
    }
  }
  if (!traced) traced = trace(gaze, p, t);
  return finish_frame(std::move(traced->samples), gaze, p, t, timing);
}

const frame& renderer::finish_frame(point_samples&& samples, gaze_point gaze, const render_params& p, frame_timing& t,
                                    frame_timing* timing) {
  if (!p.taa) reset_history();
  reconstruct(samples, gaze, p, t);
  last_samples_ = std::move(samples);
  if (timing) *timing = t;
  return frame_;
}

const frame& renderer::foveated_from(const reuse_history& other, gaze_point gaze, const render_params& p,
                                     frame_timing* timing) {
  require_set();
  if (p.adaptive.enabled || p.ray_floor > 0 || p.rolling.order != scanout::global)
    throw std::invalid_argument("foveated_from: not with adaptive refinement, a ray floor or a rolling scanout");
  if (other.valid && other.colour.size() != set_->points.size())
    throw std::invalid_argument("foveated_from: the other view's samples belong to another set");
  pending_.reset();
  frame_timing t;
  return finish_frame(trace_frame(gaze, p, frames_traced_++, t, &other).samples, gaze, p, t, timing);
}

const frame& renderer::steady_state(gaze_point gaze, const render_params& p, uint32_t frames) {
  require_set();
  if (frames < 1) throw std::invalid_argument("renderer::steady_state: no frames");
  pending_.reset();
  render_params q = p;
  q.taa = true;
  reset_history();
  last_map_.reset();  // a refinement starts afresh too
  for (uint32_t n = 0; n < frames; ++n) {
    frame_timing t;
    if (q.adaptive.enabled)
      adaptive_frame(gaze, q, n, t);
    else
      reconstruct(trace_frame(gaze, q, n, t).samples, gaze, q, t);
  }
  return frame_;
}

frame renderer::full_steady_state(const display_geometry& display, gaze_point gaze, const render_params& p, uint32_t frames,
                                  const ray_falloff* f, frame_timing* last) {
  if (frames < 1) throw std::invalid_argument("renderer::full_steady_state: no frames");
  render_params q = p;
  q.taa = true;
  taa_state history;
  frame out;
  for (uint32_t n = 0; n < frames; ++n) {
    trace_params tp = frame_trace_params(q, n);
    if (f) tp.falloff = *f;
    frame_timing t;
    const reference_trace traced = full_grid(display.width, display.height, with_lines(tp, q, display.width, display.height), &t);
    const auto t0 = clock_type::now();
    out = taa_resolve(history, traced.image, cam_, display, gaze, p.temporal);
    t.taa_ms = ms_since(t0);
    if (last) *last = t;
  }
  return out;
}

reference_trace renderer::reference(int width, int height, const render_params& p, frame_timing* t) {
  return full_grid(width, height, with_lines(base_trace(p), p, width, height), t);
}

reference_trace renderer::falloff_frame(const ray_falloff& f, const render_params& p, frame_timing* t) {
  trace_params tp = base_trace(p);
  tp.falloff = f;
  return full_grid(f.model.display.width, f.model.display.height,
                   with_lines(tp, p, f.model.display.width, f.model.display.height), t);
}

reference_trace renderer::full_grid(int width, int height, const trace_params& tp, frame_timing* t) {
  pending_.reset();
  const auto t0 = clock_type::now();
  reference_trace out = trace_reference(*scene_, cam_, width, height, tp);
  if (t) {
    *t = frame_timing{};
    t->trace_ms = ms_since(t0);
    t->rays = out.image.rays;
    t->cast = out.stats.cast;
  }
  return out;
}

warm_up_report renderer::warm_up(gaze_point gaze, const render_params& p) {
  require_set();
  if (p.adaptive.enabled) {  // one refined frame, untimed: every level's kernels and weights; nothing kept
    frame_timing t;
    const taa_state history = taa_;
    adaptive_frame(gaze, p, 0, t);
    taa_ = history;
    last_map_.reset();
    warm_up_report r;
    r.trace_ms = t.trace_ms;
    r.reconstruct_ms = t.reconstruct_ms;
    return r;
  }
  const trace_params tp = point_trace_params(p, 0);
  const auto t_index = clock_type::now();
  const std::shared_ptr<const traced_index> index = index_for(tp);
  const double index_ms = ms_since(t_index);
  const auto t0 = clock_type::now();
  const points_trace traced = trace_points(*scene_, cam_, *set_, *index, gaze, tp);
  const double trace_ms = ms_since(t0);
  warm_up_report r = prepare(traced.samples, p);
  r.trace_ms = trace_ms;
  r.traced_index_ms = index_ms;
  return r;
}

warm_up_report renderer::warm_up_reference(int width, int height, const render_params& p) {
  // The reference reads MIP levels no coarser than a 1-spp full-resolution pass builds.
  render_params once = p;
  once.spp = 1;
  warm_up_report r;
  const auto t0 = clock_type::now();
  reference(width, height, once);
  r.trace_ms = ms_since(t0);
  return r;
}

warm_up_report renderer::prepare(const point_samples& samples, const render_params& p) {
  require_set();
  warm_up_report r;
  const auto t0 = clock_type::now();
  device_->run(samples, p.reconstruct, frame_);
  r.reconstruct_ms = ms_since(t0);
  if (cached_weights_method(p.reconstruct.how) && device_->cached_weights()) r.weights_ms = 1e3 * device_->cached_weights()->seconds();
  return r;
}

}  // namespace fov
