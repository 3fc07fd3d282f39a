// The foveated frame pipeline every tool drives: trace the point set's points at the gaze,
// reconstruct (OpenCL kernels, C++ behind them), blend with TAA; or trace the
// full-resolution reference. One object owns the scene, the camera, the point set, the
// reconstruction device with its RBF weight caches, the TAA history and the trace that
// runs ahead; each stage's time is measured here and nowhere else.
#pragma once

#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>

#include "fov/adaptive.h"
#include "fov/camera.h"
#include "fov/cl_reconstruct.h"
#include "fov/frame.h"
#include "fov/labels.h"
#include "fov/pointset.h"
#include "fov/reconstruct_params.h"
#include "fov/reuse.h"
#include "fov/rolling.h"
#include "fov/scene.h"
#include "fov/stereo.h"
#include "fov/taa.h"
#include "fov/trace.h"

namespace fov {

// How the rays of consecutive TAA frames differ (without TAA the pattern stays fixed:
// nothing integrates new positions).
enum class ray_pattern : uint8_t {
  reseed,  // new ray positions every frame (seed + frame number)
  mirror,  // the set mirrored in turn: four patterns from one set (thesis Sec. 3.3)
  fixed,   // the same rays every frame (what the thesis's static view sees)
};
inline constexpr std::pair<const char*, ray_pattern> ray_pattern_labels[] = {
    {"reseed", ray_pattern::reseed}, {"mirror", ray_pattern::mirror}, {"fixed", ray_pattern::fixed}};

// Everything that decides a frame. Every tool parses its flags (or its protocol) into one.
struct render_params {
  // Tracing.
  uint32_t spp = 32;  // rays per point (foveated) or per pixel (reference), 1..max_spp
  uint64_t seed = 1;  // the ray positions
  bool shadows = true;
  texture_footprint footprint = texture_footprint::disc;
  pixel_sampler reference_sampler = pixel_sampler::sobol;  // full-resolution pixels' ray positions (grid points' too)
  pixel_sampler disc_sampler = pixel_sampler::random;      // foveated points' ray positions (the thesis's)
  // Foveated points' rays fall with eccentricity from spp at the gaze to this floor
  // (trace_params::ray_floor, point_ray_rule); 0 = spp at every point (the thesis).
  uint32_t ray_floor = 0;
  float exposure_ev = 0;  // every colour times 2^exposure_ev (trace_params::exposure_ev)
  // How a ray's colour is found (trace_params::method) and, for the path integrator, the
  // bounces after the first hit (0..max_bounces).
  integrator method = integrator::direct;
  uint32_t bounces = 2;
  // A lat-long image that surrounds and lights the scene (load_scene's env_light; read when
  // the tools load their scenes); "" for the scene's own environment.
  std::string env_light;
  // A directional sun replacing the scene's light when either is set (the other part
  // then the default light's): direction towards the light, irradiance per channel.
  std::optional<glm::vec3> sun_direction, sun_irradiance;
  // Reconstruction (its k also decides which off-screen points are traced).
  reconstruct_params reconstruct;
  // Temporal anti-aliasing.
  bool taa = false;
  ray_pattern pattern = ray_pattern::reseed;
  taa_params temporal;
  // Per-frame refinement of a nested set (fov/adaptive.h); a nested set without it is traced
  // and reconstructed as its finest level, a fixed set.
  adaptive_params adaptive;
  // Where reconstruction runs (read when a point set is put in use).
  reconstruct_device device = reconstruct_device::opencl;
  // Cached-weight configurations (method, k, kernel, shape) kept at once: a tool that
  // alternates more of them than this computes their weights again at each switch
  // (cl_reconstructor; read when a point set is put in use).
  uint32_t weight_caches = cl_reconstructor::default_weight_caches;
  // The camera (read when the renderer is made).
  camera_overrides view;
  // A rolling display (fov/rolling.h): the order its lines are shown in, the frame period,
  // and the camera path the view moves along (the renderer's camera is the path's at
  // rolling.start_ms; each line's rays are cast from the path's camera when that line is shown).
  rolling_params rolling;
  // Temporal reuse (fov/reuse.h): foveated frames keep earlier frames' samples where they
  // still hold (not with adaptive refinement, a ray floor or a rolling scanout; no trace runs
  // ahead). Its mode `eyes` is the stereo renderer's (fov/stereo_renderer.h): a renderer
  // traces every point then, and foveated_from keeps another view's samples.
  reuse_params reuse;
  // Two eyes (fov/stereo.h): read by the stereo renderer; a renderer draws one eye.
  stereo_params stereo;
};

// The empty string when `p` is valid (for `set`'s k when given), else the reason, naming
// the setting as the tools' flags do (e.g. "--spp must lie in 1..65535 (got 0)").
std::string validate(const render_params& p, const pointset* set = nullptr);

// The seeds of two converged references (docs/metrics.md) for frames rendered with
// `seed`: drawn from it, so they share no ray position with its full-resolution frames
// (seed) or TAA frames (seed + n), and differ from each other (the noise floor).
std::pair<uint64_t, uint64_t> converged_seeds(uint64_t seed);

// What one frame cost, in milliseconds of wall time, and what it traced.
//  - trace_ms: trace_points (on a trace that ran ahead: its own duration);
//  - reconstruct_ms: reconstruction into the renderer's reused frame, TAA excluded;
//  - taa_ms: on the device, the TAA kernel's time; on the C++ path, taa_resolve's.
struct frame_timing {
  double trace_ms = 0, reconstruct_ms = 0, taa_ms = 0;
  bool traced_ahead = false;  // the trace ran in the background (begin_trace)
  double trace_wait_ms = 0;   // how long the frame still waited for it
  uint64_t rays = 0, points_traced = 0;
  // Every ray the frame's trace cast, by kind (trace_stats::cast): primary (as many as
  // `rays`), shadow, and the path integrator's bounces.
  ray_counts cast;
  bool on_device = false;
  weight_stats weights;
  // An adaptive frame (render_params::adaptive): rays and points per level, blocks per level.
  // Its trace_ms is every level's trace and the refinement's choices; its reconstruct_ms
  // every level's reconstruction (one per level a block reads) and their composite.
  bool adaptive = false;
  adaptive_report refinement;
  // A frame with temporal reuse (render_params::reuse): what it kept and traced. Its `rays`
  // and cast.primary count the traced points' rays and the probes.
  bool reused = false;
  reuse_report reuse;
  double total_ms() const { return trace_ms + reconstruct_ms + taa_ms; }
};

// What warm_up spent, untimed in every frame after it.
struct warm_up_report {
  double trace_ms = 0;        // textures read and MIP-mapped on first use
  double reconstruct_ms = 0;  // the first launch: kernel compilation for its shape, RBF weights
  double weights_ms = 0;  // the RBF weights alone (their one-time solve)
  double traced_index_ms = 0;  // make_traced_index for the set and k (0 when already made)
};

class renderer {
 public:
  // The camera is setup_camera(scene, p.view); p.device is kept for use_pointset.
  renderer(std::shared_ptr<const scene> s, const render_params& p);
  ~renderer();
  renderer(const renderer&) = delete;
  renderer& operator=(const renderer&) = delete;

  // Uses `set` from now on: builds its device state (seconds on a big set) and drops the
  // TAA history. The same set again changes nothing.
  void use_pointset(std::shared_ptr<const pointset> set);
  const pointset* current_set() const { return set_.get(); }
  camera& cam() { return cam_; }
  const camera& cam() const { return cam_; }
  const scene& current_scene() const { return *scene_; }

  const std::string& device() const;  // what reconstructs: the OpenCL device's name, or "C++ (TBB)"
  bool on_device() const;
  // Why OpenCL is not in use although p.device asked for it (empty when it is, or when
  // cpp was asked for); the tools print it as a warning.
  std::string device_problem() const;
  // The warning the tools print for it: "warning: REASON; using the C++ path" (empty
  // when there is nothing to say).
  std::string device_warning() const;
  double device_setup_ms() const { return device_setup_ms_; }

  // The stages, for tools that time or combine them themselves (fovbench):
  // trace() casts the next frame's rays (the pattern advances by one frame);
  points_trace trace(gaze_point gaze, const render_params& p, frame_timing& t);
  // reconstruct() rebuilds the frame into the renderer's reused storage, then blends it
  // with the TAA history when p.taa (the history is left alone otherwise).
  const frame& reconstruct(const point_samples& samples, gaze_point gaze, const render_params& p, frame_timing& t);

  // The same two stages for an adaptive frame (p.adaptive, a nested set in use): the levels'
  // trace and the refinement (the pattern advances by one frame; a still view keeps the last
  // refinement), then every level in use reconstructed, composited and blended with the TAA
  // history when p.taa (on the host).
  adaptive_trace trace_refined(gaze_point gaze, const render_params& p, frame_timing& t);
  const frame& reconstruct_refined(const adaptive_trace& a, gaze_point gaze, const render_params& p, frame_timing& t);

  // One foveated frame at the gaze (trace, or take the trace begun ahead, then
  // reconstruct), valid until the next call. Without TAA the history is dropped, so
  // turning TAA on starts afresh.
  const frame& foveated(gaze_point gaze, const render_params& p, frame_timing* t = nullptr);
  // One foveated frame at the gaze whose points keep, where they hold, the samples another
  // view traced of the same set (`other`: the other eye's, fov/stereo.h history_of), and
  // trace the rest: trace_reusing with `other` as the last frame and p.reuse's fovea and
  // threshold (not its age: `other` is of this instant). The frame's timing reports what it
  // kept (reused, reuse) as temporal reuse's does. Not with adaptive refinement, a ray floor
  // or a rolling scanout (validate refuses them with p.reuse.mode eyes).
  const frame& foveated_from(const reuse_history& other, gaze_point gaze, const render_params& p,
                             frame_timing* t = nullptr);
  // The samples the last foveated() frame traced (with adaptive refinement: none, empty).
  const point_samples& last_samples() const { return last_samples_; }
  // Pipelining: starts tracing the frame for this gaze, camera and params in the
  // background, so it overlaps whatever the caller does next (showing the frame before).
  // The next foveated() with the same gaze, camera (cam() set to `view`), tracing params
  // and set takes those samples; any other call drops them and traces anew.
  void begin_trace(gaze_point gaze, const camera& view, const render_params& p);

  // Steady state under TAA (issue 24): `frames` (>= 1) foveated frames of the still view at
  // the gaze, frame n traced in the pattern of frame n (frame_trace_params with p.taa:
  // p.pattern, from frame 0 whatever was traced before) and reconstructed with TAA
  // (p.temporal, on the device or in C++) from an empty history; returns the last output,
  // which is then the TAA history. The same params give the same frame on any renderer.
  const frame& steady_state(gaze_point gaze, const render_params& p, uint32_t frames);
  // The same for the full pixel grid: reference(), or falloff_frame(*f), traced in pattern n
  // for frame n (reseed: seed + n; mirror: each pixel's samples m spp .. (m + 1) spp - 1 with
  // m = n mod 4, as a grid point's) and blended by taa_resolve on `display` at `gaze` from a
  // history of its own (the foveated history is left alone). `last`, when given, gets the
  // last frame's trace and TAA resolve times and its rays.
  frame full_steady_state(const display_geometry& display, gaze_point gaze, const render_params& p, uint32_t frames,
                          const ray_falloff* f = nullptr, frame_timing* last = nullptr);

  // The full-resolution reference, p.spp rays per pixel (no TAA, no pattern).
  reference_trace reference(int width, int height, const render_params& p, frame_timing* t = nullptr);
  // Full resolution at a foveated sampling rate (fov::ray_falloff): every pixel of f's
  // display traced, its rays falling from p.spp at f.gaze to f.floor; no sparse points, no
  // reconstruction (issue 24). A flat rule (f.floor == p.spp) is reference(), bit for bit.
  reference_trace falloff_frame(const ray_falloff& f, const render_params& p, frame_timing* t = nullptr);

  // A nested set's levels (make_levels; null for a fixed set), built by use_pointset, and the
  // last adaptive frame's refinement map (null before one): the debug view draws it.
  const nested_levels* levels() const { return levels_.get(); }
  const refinement_map* last_refinement() const { return last_map_ ? &*last_map_ : nullptr; }
  double levels_setup_ms() const { return levels_setup_ms_; }

  // Untimed first use: one trace (textures, MIP levels) and one reconstruction (kernel
  // compilation, RBF weights for the screen's tiles) at this gaze. Neither the pattern
  // nor the TAA history moves.
  warm_up_report warm_up(gaze_point gaze, const render_params& p);
  warm_up_report warm_up_reference(int width, int height, const render_params& p);  // one 1-spp pass
  // The untimed first reconstruction alone, for samples traced elsewhere.
  warm_up_report prepare(const point_samples& samples, const render_params& p);

  void reset_history() { taa_ = taa_state{}; }
  // Drops the samples temporal reuse keeps (the next frame traces every point).
  void reset_reuse() { reuse_.clear(); }
  // Treats the TAA history as seen with the gaze at `g` (a saccade's onset, when it lands):
  // the next frame's pixels whose eccentricity dropped by taa_params::focus_lag_deg since then
  // (the new fovea) take the current frame, on the device and in C++ alike.
  void history_gaze(gaze_point g) {
    if (taa_.valid) taa_.gaze = g;
  }
  uint64_t frames_traced() const { return frames_traced_; }

  // The trace_params of the frame numbered `n` under p (n counts the renderer's traces).
  static trace_params frame_trace_params(const render_params& p, uint64_t n);
  // tp with a camera per line for a width x height screen when p.rolling asks for them.
  trace_params with_lines(trace_params tp, const render_params& p, int width, int height) const;
  // The trace_params of foveated frame n on the set in use: frame_trace_params with its lines.
  trace_params point_trace_params(const render_params& p, uint64_t n) const;

 private:
  std::shared_ptr<const scene> scene_;
  camera cam_;
  reconstruct_device device_kind_;
  uint32_t weight_caches_;
  std::shared_ptr<const pointset> set_;
  // Finds each frame's traced points (make_traced_index), for set_ and the last k traced.
  std::shared_ptr<const traced_index> index_;
  std::shared_ptr<const traced_index> index_for(const trace_params& tp);
  // The trace of frame number n under p (frame_trace_params), timed: trace() and steady_state().
  // With `other`, the points keep other's samples where they hold (foveated_from).
  points_trace trace_frame(gaze_point gaze, const render_params& p, uint64_t n, frame_timing& t,
                           const reuse_history* other = nullptr);
  // Every pixel of a width x height frame traced with tp (reference, falloff_frame), timed.
  reference_trace full_grid(int width, int height, const trace_params& tp, frame_timing* t);
  std::unique_ptr<cl_reconstructor> device_;
  double device_setup_ms_ = 0;
  // Nested sets: the levels, a reconstructor per coarser level (the finest is device_), the
  // last refinement and the camera and params it was made under.
  std::shared_ptr<const nested_levels> levels_;
  std::vector<std::unique_ptr<cl_reconstructor>> level_devices_;
  double levels_setup_ms_ = 0;
  std::optional<refinement_map> last_map_;
  camera last_map_camera_;
  adaptive_params last_map_params_;
  // A traced frame's rest: reconstruct (with TAA when p.taa, else the history dropped), keep
  // the samples as last_samples_, report the timing.
  const frame& finish_frame(point_samples&& samples, gaze_point gaze, const render_params& p, frame_timing& t,
                            frame_timing* timing);
  // An adaptive frame numbered n (trace, reconstruct every level in use, composite, TAA).
  const frame& adaptive_frame(gaze_point gaze, const render_params& p, uint64_t n, frame_timing& t);
  adaptive_trace trace_refined_frame(gaze_point gaze, const render_params& p, uint64_t n, frame_timing& t);
  frame level_frame_;  // one level's reconstruction before the composite
  taa_state taa_;
  reuse_history reuse_;
  render_params reuse_params_;  // the params reuse_ was traced with
  uint64_t frames_traced_ = 0;
  frame frame_;  // what reconstruct() and foveated() return
  point_samples last_samples_;  // what the last foveated() frame traced

  struct pending_trace {
    gaze_point gaze;
    camera view;
    render_params params;
    std::shared_ptr<const pointset> set;
    std::future<std::pair<points_trace, double>> result;  // the trace and its ms
  };
  std::optional<pending_trace> pending_;  // last: waited for before the rest goes
  void require_set() const;
};

}  // namespace fov
