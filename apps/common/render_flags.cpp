#include "render_flags.h"

#include <sstream>

#include <fmt/format.h>

#include "camera_path.h"

namespace fov {

namespace {

glm::vec3 parse_triple(const std::string& flag, const std::string& text) {
  glm::vec3 v;
  char comma[2] = {0, 0}, extra = 0;
  std::istringstream in(text);
  if (!(in >> v.x >> comma[0] >> v.y >> comma[1] >> v.z) || comma[0] != ',' || comma[1] != ',' || (in >> extra))
    throw CLI::ValidationError(flag, "expected X,Y,Z (got '" + text + "')");
  return v;
}

}  // namespace

void add_render_flags(CLI::App& app, render_params& p, unsigned groups) {
  if (groups & flags_spp)
    app.add_option("--spp", p.spp, "Rays per point (foveated) or per pixel (reference)")
        ->check(CLI::Range(1u, max_spp))
        ->capture_default_str();
  if (groups & flags_trace) {
    app.add_option("--seed", p.seed, "Seed of the ray positions")->capture_default_str();
    app.add_flag("--no-shadows", [&p](int64_t) { p.shadows = false; }, "Skip shadow rays");
    add_label_option(app, "--integrator", p.method, integrator_labels,
                     "How a ray's colour is found: direct (the light at the first hit plus an ambient term) or path "
                     "(path tracing: the light at every vertex, the environment and emission by bounces)");
    app.add_option("--bounces", p.bounces, "With --integrator path: bounces after the first hit")
        ->check(CLI::Range(0u, max_bounces))
        ->capture_default_str();
    app.add_option("--env-light", p.env_light,
                   "A lat-long environment image that surrounds and lights the scene (the path integrator samples it as "
                   "a light; the direct one uses its mean as ambient light)")
        ->check(CLI::Validator(
            [](std::string& file) {
              const std::string why = env_image_problem(file);
              return why.empty() ? why : file + ": " + why;
            },
            "IMAGE"));
    add_label_option(app, "--texture-footprint", p.footprint, texture_footprint_labels,
                     "Foveated rays filter textures over their share of the point's disc (disc: the thesis's "
                     "prefilter) or of a pixel (pixel: sharper, cheaper, aliased periphery)");
    app.add_option("--exposure", p.exposure_ev, "Exposure in EV: every colour times 2^EV, then clamped for display")
        ->capture_default_str();
    app.add_option_function<std::string>(
        "--sun-dir", [&p](const std::string& t) { p.sun_direction = parse_triple("--sun-dir", t); },
        "Replace the scene's lights by a sun in direction X,Y,Z (towards the light)");
    app.add_option_function<std::string>(
        "--sun-irradiance",
        [&p](const std::string& t) {
          if (t.find(',') != std::string::npos) {
            p.sun_irradiance = parse_triple("--sun-irradiance", t);
            return;
          }
          char* end = nullptr;
          const double v = std::strtod(t.c_str(), &end);
          if (t.empty() || *end) throw CLI::ValidationError("--sun-irradiance", "expected V or R,G,B (got '" + t + "')");
          p.sun_irradiance = glm::vec3(float(v));
        },
        "Replace the scene's lights by a sun of this irradiance (V or R,G,B; white albedo facing it: V + ambient)");
    add_label_option(app, "--disc-sampler", p.disc_sampler, pixel_sampler_labels,
                     "Foveated rays inside each point's disc: random (independent uniform positions, the thesis's) or "
                     "sobol (scrambled Sobol, concentric map: stratified)");
    add_label_option(app, "--reference-sampler", p.reference_sampler, pixel_sampler_labels,
                     "Full-resolution rays inside each pixel, and a grid fovea's: sobol (Owen-scrambled Sobol: stratified, converges) or "
                     "random (independent uniform positions)");
  }
  if (groups & flags_method) {
    add_label_option(app, "--method", p.reconstruct.how, method_labels, "Reconstruction");
    app.add_option("--k", p.reconstruct.k, "Neighbours each pixel reads (1..the set's k)")->capture_default_str();
  }
  if (groups & flags_reconstruct) {
    app.add_flag("--renka", p.reconstruct.renka, "Shepard with Renka's squared weights");
    add_label_option(app, "--rbf-kernel", p.reconstruct.kernel, rbf_kernel_labels, "RBF kernel");
    app.add_option("--rbf-shape", p.reconstruct.shape, "RBF shape c in units of the neighbours' mean spacing p")
        ->capture_default_str();
  }
  if (groups & flags_pattern)
    add_label_option(app, "--pattern", p.pattern, ray_pattern_labels,
                     "With TAA, how each frame's rays differ: reseed (new positions), mirror (the set mirrored: four "
                     "patterns, thesis Sec. 3.3) or fixed");
  if (groups & flags_device)
    add_label_option(app, "--device", p.device, reconstruct_device_labels,
                     "Reconstruct with OpenCL (falls back to C++ with a warning) or C++");
  if (groups & flags_adaptive) {
    app.add_flag("--adaptive", p.adaptive.enabled,
                 "Refine a nested set (fovgen --levels) per frame where its samples' contrast would be visible "
                 "(docs/adaptive.md)");
    app.add_option("--adaptive-threshold", p.adaptive.threshold,
                   "Refine where contrast reaches this x the acuity model's threshold (1: the model's limit; 0: refine "
                   "everywhere)")
        ->check(CLI::Range(0.0, max_adaptive_threshold))
        ->capture_default_str();
    app.add_option("--adaptive-depth", p.adaptive.depth_ratio,
                   "Also refine where depths differ by more than this fraction of the nearest, or hits meet misses (0: off)")
        ->check(CLI::Range(0.0, max_depth_ratio))
        ->capture_default_str();
    app.add_option("--adaptive-budget", p.adaptive.budget, "Rays per frame, the coarsest level's included (0: no limit)")
        ->check(CLI::Range(uint64_t(0), uint64_t(1) << 40))
        ->capture_default_str();
  }
  if (groups & flags_reuse) {
    add_label_option(app, "--reuse", p.reuse.mode, reuse_mode_labels,
                     "Keep earlier frames' samples (temporal) or, with --stereo, the left eye's in the right eye "
                     "(eyes) where a probe ray says they still hold (docs/reuse.md)");
    app.add_option("--reuse-fovea", p.reuse.fovea_deg,
                   "With --reuse: points within this eccentricity (degrees) are always traced; full "
                   "confidence from 3x it")
        ->check(CLI::Range(0.0, max_reuse_fovea_deg))
        ->capture_default_str();
    app.add_option("--reuse-threshold", p.reuse.threshold, "With --reuse: the least confidence a kept sample needs")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    app.add_option("--reuse-max-age", p.reuse.max_age, "With --reuse temporal: the most frames in a row a sample is kept")
        ->check(CLI::Range(1u, max_reuse_age))
        ->capture_default_str();
    app.add_option("--reuse-budget", p.reuse.budget,
                   "With --reuse: the most rays a frame's traced points cast (probes not counted; 0: no limit); "
                   "points with no sample near are traced regardless, the least confident of the rest first")
        ->check(CLI::Range(uint64_t(0), max_reuse_budget))
        ->capture_default_str();
    add_label_option(app, "--reuse-edges", p.reuse.edges, reuse_edges_labels,
                     "With --reuse: the last frame's edges that keep their neighbours traced: silhouettes and "
                     "sloped discs (strict), or silhouettes only");
    add_label_option(app, "--reuse-distance", p.reuse.distance, reuse_distance_labels,
                     "With --reuse: where a kept sample's distance from what the point sees is measured: in the "
                     "world against the disc at that depth, or on the screen against the point's spacing");
    app.add_option("--reuse-view", p.reuse.view_deg,
                   "With --reuse: the most the view onto a kept sample's surface may turn, degrees (0: no limit); "
                   "glossy shading moves with it")
        ->check(CLI::Range(0.0, max_reuse_view_deg))
        ->capture_default_str();
  }
  if (groups & flags_stereo) {
    app.add_flag("--stereo", p.stereo.enabled,
                 "Two eyes side by side, each the set's screen with its own gaze (--gaze-right) and a camera half "
                 "--ipd to its side of the head's (docs/reuse.md)");
    app.add_option("--ipd", p.stereo.ipd_mm, "With --stereo: interpupillary distance in mm of a world in metres")
        ->check(CLI::Range(0.0, max_ipd_mm))
        ->capture_default_str();
  }
  if (groups & flags_view) {
    app.add_option("--hfov", p.view.hfov_deg, "Horizontal field of view in degrees (default: the scene's camera, else 90)");
    const auto point = parse_triple;
    CLI::Option* eye = app.add_option_function<std::string>(
        "--eye", [&p, point](const std::string& t) { p.view.eye = point("--eye", t); },
        "Camera position X,Y,Z in world units (default: the scene camera's)");
    CLI::Option* target = app.add_option_function<std::string>(
        "--look-at", [&p, point](const std::string& t) { p.view.target = point("--look-at", t); },
        "Point X,Y,Z the camera looks at (default: along the scene camera's direction)");
    app.add_option_function<std::string>(
        "--up", [&p, point](const std::string& t) { p.view.up = point("--up", t); },
        "Camera up direction X,Y,Z (default: the scene camera's)");
    CLI::Option* path =
        app.add_option_function<std::string>(
               "--camera",
               [&p](const std::string& file) {
                 // The renderer's camera is the path's at rolling.start_ms: its first row's time
                 // unless --camera-time (bound after this flag, so its value is set after) says.
                 // The first row is also the view's eye and target, which setup_camera checks.
                 p.rolling.path = std::make_shared<const camera_path>(load_camera_path(file));
                 p.rolling.start_ms = p.rolling.path->keys[0].t;
                 const camera_path::key& first = p.rolling.path->keys[0];
                 p.view.eye = glm::vec3(float(first.eye[0]), float(first.eye[1]), float(first.eye[2]));
                 p.view.target = glm::vec3(float(first.target[0]), float(first.target[1]), float(first.target[2]));
               },
               (groups & flags_rolling)
                   ? "A camera path CSV t_ms,x,y,z,tx,ty,tz (docs/fovview.md): the camera at --camera-time on it"
                   : "A camera path CSV t_ms,x,y,z,tx,ty,tz (docs/fovview.md): its first row's eye and target")
            ->excludes(eye)
            ->excludes(target);
    if (groups & flags_rolling) {
      app.add_option("--camera-time", p.rolling.start_ms,
                     "The time (ms) on the --camera path at which the frame's scanout begins (default: its first row's)")
          ->check(CLI::Range(-max_camera_time_ms, max_camera_time_ms))
          ->needs(path);
      add_label_option(app, "--rolling", p.rolling.order, scanout_labels,
                       "A rolling display: the order its lines are shown in, each line traced from the --camera path's "
                       "camera when it is shown (docs/reuse.md)");
      app.add_option("--frame-period", p.rolling.frame_period_ms,
                     "With --rolling: the scanout's duration, first line to last (ms; 90 Hz: 11.1)")
          ->check(CLI::Range(min_frame_period_ms, max_frame_period_ms))
          ->capture_default_str();
    }
  }
}

std::shared_ptr<const pointset> select_level(std::shared_ptr<const pointset> set, int level, const std::string& file) {
  if (level < 0) return set;
  if (!set->nested() || uint32_t(level) >= set->level_count())
    throw usage_error(set->nested() ? fmt::format("--level {}: {} has levels 0..{} (0 the coarsest)", level, file,
                                                  set->level_count() - 1)
                                    : fmt::format("--level {}: {} is not a nested set (fovgen --levels)", level, file));
  const nested_levels levels = make_levels(set);
  return levels.levels[size_t(level)].set;
}

nlohmann::json reuse_json(const reuse_report& r) {
  nlohmann::json bands = nlohmann::json::array();
  for (size_t b = 0; b < reuse_bands; ++b)
    bands.push_back({{"from_deg", b == 0 ? 0.0 : reuse_band_edges_deg[b - 1]},
                     {"to_deg", b + 1 < reuse_bands ? nlohmann::json(reuse_band_edges_deg[b]) : nlohmann::json(nullptr)},
                     {"points", r.points_by_band[b]},
                     {"reused", r.reused_by_band[b]}});
  nlohmann::json verdicts;
  for (const auto& [label, v] : reuse_verdict_labels) verdicts[label] = r.by_verdict[size_t(v)];
  return {{"points", r.points},           {"reused", r.reused},           {"traced", r.traced},
          {"probe_rays", r.probe_rays},   {"rays_traced", r.rays_traced}, {"rays_reused", r.rays_reused},
          {"reused_share", r.reused_share()}, {"kept_for_budget", r.kept_for_budget}, {"budget_short", r.budget_short},
          {"by_eccentricity", bands}, {"by_verdict", verdicts},
          {"ms", {{"probe", r.ms_probe}, {"decide", r.ms_decide}, {"trace", r.ms_trace}, {"history", r.ms_history}}}};
}

nlohmann::json refinement_json(const frame_timing& t, const render_params& p, const nested_levels& levels) {
  nlohmann::json j;
  j["threshold"] = p.adaptive.threshold;
  j["depth_ratio"] = p.adaptive.depth_ratio;
  j["budget"] = p.adaptive.budget;
  j["budget_short"] = t.refinement.budget_short;
  j["points_refined"] = t.refinement.points_refined;
  j["refinements_left_out"] = t.refinement.refinements_left_out;
  j["blocks_kept"] = t.refinement.blocks_kept;
  j["block_pixels"] = refinement_block;
  nlohmann::json per = nlohmann::json::array();
  for (size_t l = 0; l < levels.levels.size() && l < t.refinement.rays_per_level.size(); ++l)
    per.push_back({{"level", l},
                   {"scale", levels.levels[l].scale},
                   {"rays", t.refinement.rays_per_level[l]},
                   {"points", t.refinement.points_per_level[l]},
                   {"blocks", t.refinement.blocks_per_level[l]}});
  j["levels"] = per;
  return j;
}

std::string refinement_warning(const frame_timing& t, const render_params& p) {
  if (!t.adaptive || !t.refinement.budget_short) return "";
  return fmt::format("warning: --adaptive-budget {} rays is below the coarsest level's {}: traced it alone, nothing refined",
                     p.adaptive.budget, t.refinement.rays_per_level.empty() ? 0 : t.refinement.rays_per_level[0]);
}

void require_valid(const render_params& p, const pointset* set) {
  const std::string problem = validate(p, set);
  if (!problem.empty()) throw usage_error(problem);
}

}  // namespace fov
