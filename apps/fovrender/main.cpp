// fovrender: renders one frame headless, foveated or at full resolution, and compares.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "../common/cli.h"
#include "../common/compare_command.h"
#include "../common/debug_views.h"
#include "../common/image_io.h"
#include "../common/render_flags.h"
#include "fov/flicker.h"
#include "fov/metrics.h"
#include "fov/files.h"
#include "fov/pointset_io.h"
#include "fov/renderer.h"
#include "fov/speedup.h"
#include "fov/stereo_renderer.h"

namespace {

using json = nlohmann::json;
using fov::usage_error;

// What fovrender does beyond the render parameters.
struct render_options {
  std::string scene = "builtin", points, gaze = "centre", compare, debug_output, flip_map, foveated_flip_map;
  std::string gaze_right;  // with --stereo: the right eye's gaze (default: --gaze)
  std::vector<std::string> outputs;
  fov::debug_view debug = fov::debug_view::points;
  bool debug_asked = false;  // --debug-view given
  bool reference = false, no_warmup = false, json = false, no_flip = false, no_jod = false;
  bool photometry_given = false;  // --peak-luminance, --contrast or --ambient given
  fov::display_photometry photometry;
  bool size_given = false;  // --width or --height given
  int width = 1280, height = 1440;  // without --points
  std::string display;              // without --points: a display spec instead of --width/--height
  double viewing_distance = 1.0;    // from --display
  uint32_t taa_frames = 0;
  uint32_t speedup = 0;  // repetitions of the paired timing (0: none)
  uint32_t reference_spp = 0;  // compare against a converged reference traced here (0: none)
  uint32_t ray_floor = 0;      // rays fall from --spp at the gaze to this (0: --spp everywhere)
  double falloff_scale = 1.0;  // the acuity model's scale s the falloff follows
  bool falloff_scale_given = false;
  int level = -1;  // one level of a nested set as a fixed set (-1: the whole set)
  uint32_t flicker = 0;  // frames of the flicker path (0: none)
  bool path_given = false;  // --flicker-yaw, --flicker-shift or --flicker-gaze given
  fov::flicker_params path;  // its turn, shift and gaze drift a frame
};

// Temporal reuse along the --flicker path as JSON: per sequence the rays a frame cast (mean
// over the frames after the first, which has nothing to reuse): primary rays (with reuse the
// probes too) and every ray (shadow and bounce rays too); flicker and video JOD.
json reuse_path_json(const fov::reuse_path_report& rp, const fov::flicker_params& fp) {
  json frames = json::array();
  for (size_t n = 0; n < rp.reuse.size(); ++n) {
    json f = fov::reuse_json(rp.reuse[n]);
    f["rays"] = rp.rays_reuse[n];
    f["rays_full"] = rp.rays_full[n];
    f["all_rays"] = rp.cast_reuse[n];
    f["all_rays_full"] = rp.cast_full[n];
    frames.push_back(f);
  }
  const double full = fov::mean_after_first(rp.rays_full), reused = fov::mean_after_first(rp.rays_reuse);
  const double all_full = fov::mean_after_first(rp.cast_full), all_reused = fov::mean_after_first(rp.cast_reuse);
  json j{{"frames", fp.frames},
         {"yaw_deg_per_frame", fp.yaw_deg_per_frame},
         {"shift_per_frame", fp.shift_per_frame},
         {"gaze_px_per_frame", fp.gaze_px_per_frame},
         {"rays_full", full},
         {"rays_reuse", reused},
         {"rays_ratio", full > 0 ? reused / full : 0.0},
         {"all_rays_full", all_full},
         {"all_rays_reuse", all_reused},
         {"all_rays_ratio", all_full > 0 ? all_reused / all_full : 0.0},
         {"flicker_full", rp.flicker_full},
         {"flicker_reuse", rp.flicker_reuse},
         {"per_frame", frames}};
  if (rp.has_jod) j["jod_full"] = rp.jod_full.jod, j["jod_reuse"] = rp.jod_reuse.jod;
  if (!rp.trace_ms_full.empty()) {
    const std::vector<double> ratio = rp.trace_ratios();
    const fov::timing r = fov::summarise(ratio);
    j["trace_time"] = {{"pairs", ratio.size()},
                       {"ms_full_median", fov::summarise(rp.trace_ms_full).median},
                       {"ms_reuse_median", fov::summarise(rp.trace_ms_reuse).median},
                       {"ratio_median", r.median},
                       {"ratio_min", r.min},
                       {"ratio_max", r.max}};
  }
  return j;
}

// The flags that only make sense together, before anything is read or rendered (exit 2).
void check_options(const render_options& o, const fov::render_params& p) {
  if (o.outputs.empty() && o.compare.empty() && o.reference_spp == 0)
    throw usage_error("nothing to do: give -o, --compare or --reference-spp");
  if (o.debug_asked && o.debug_output.empty() && o.outputs.empty()) throw usage_error("--debug-view needs -o or --debug-output");
  if (!o.reference && o.points.empty()) throw usage_error("--points is required unless --reference");
  if (!o.points.empty() && o.size_given) throw usage_error("--width/--height: the set gives the screen size; drop them with --points");
  // A frame's buffers (colour, depth, samples, the file's pixels) take a few tens of bytes a
  // pixel: a size the range check passes may still not fit (65536 x 65536 is 275 GB).
  if (o.points.empty())
    if (const std::string why = fov::memory_problem(uint64_t(o.width) * uint64_t(o.height) * (p.stereo.enabled ? 128 : 64),
                                                    fmt::format("{} {} x {} frame{} (about 64 bytes a pixel)",
                                                                p.stereo.enabled ? "two" : "a", o.width, o.height,
                                                                p.stereo.enabled ? "s" : ""));
        !why.empty())
      throw usage_error("--width/--height: " + why);
  if (o.reference && o.speedup > 0) throw usage_error("--speedup compares a foveated frame with --reference; give --points instead");
  if (o.falloff_scale_given && (o.ray_floor == 0 || !o.reference))
    throw usage_error("--falloff-scale needs --reference --ray-floor (a point set's rays follow the set's own scale)");
  if (o.ray_floor > p.spp)
    throw usage_error(fmt::format("--ray-floor {} exceeds --spp {}: rays fall from --spp at the gaze", o.ray_floor, p.spp));
  if (!(o.falloff_scale > 0 && o.falloff_scale <= 10)) throw usage_error("--falloff-scale must lie in (0, 10]");
  const bool comparing = !o.compare.empty() || o.reference_spp > 0;
  if (!o.compare.empty() && o.reference_spp > 0) throw usage_error("give --compare or --reference-spp, not both");
  if (o.reference_spp > 0 && o.reference_spp <= p.spp)
    throw usage_error(fmt::format("--reference-spp {} must exceed --spp {}: a reference must be better than the frame",
                                  o.reference_spp, p.spp));
  if (!comparing && !(o.flip_map.empty() && o.foveated_flip_map.empty() && !o.no_flip))
    throw usage_error("--no-flip, --flip-map and --foveated-flip-map need --compare or --reference-spp");
  if (o.no_flip && !(o.flip_map.empty() && o.foveated_flip_map.empty()))
    throw usage_error("--no-flip leaves no FLIP map to write");
  if (!comparing && (o.no_jod || o.photometry_given))
    throw usage_error("--no-jod, --peak-luminance, --contrast and --ambient need --compare or --reference-spp");
  if (o.no_jod && o.photometry_given) throw usage_error("--no-jod: the display's light is for JOD only");
  if (o.level >= 0 && p.adaptive.enabled) throw usage_error("--level renders one level as a fixed set; --adaptive refines them all");
  if (o.level >= 0 && o.points.empty()) throw usage_error("--level needs --points (a nested set)");
  if (o.flicker > 0 && o.reference) throw usage_error("--flicker measures a point set's frames; drop --reference");
  if (o.flicker > 0 && p.rolling.order != fov::scanout::global)
    throw usage_error("--flicker turns the camera itself; drop --rolling");
  if (o.flicker == 0 && o.path_given) throw usage_error("--flicker-yaw, --flicker-shift and --flicker-gaze need --flicker");
  if (p.adaptive.enabled && o.reference) throw usage_error("--adaptive refines a point set; drop --reference");
  if (p.reuse.mode != fov::reuse_mode::none && o.reference)
    throw usage_error("--reuse keeps a point set's samples across frames; drop --reference");
  if (o.debug_asked && o.debug == fov::debug_view::refinement && !p.adaptive.enabled)
    throw usage_error("--debug-view refinement needs --adaptive");
  if (!p.stereo.enabled && !o.gaze_right.empty()) throw usage_error("--gaze-right is the right eye's: give --stereo");
  if (p.stereo.enabled) {
    const std::pair<bool, const char*> one_eye_only[] = {
        {o.speedup > 0, "--speedup"}, {o.flicker > 0, "--flicker"}, {o.debug_asked, "--debug-view"},
        {!o.compare.empty(), "--compare (--reference-spp compares each eye with its own converged reference)"},
        {!o.flip_map.empty() || !o.foveated_flip_map.empty(), "--flip-map and --foveated-flip-map"},
        {o.ray_floor > 0, "--ray-floor"}};
    for (const auto& [given, flag] : one_eye_only)
      if (given) throw usage_error(fmt::format("--stereo does not take {}", flag));
  }
}

// The point set's description: the scheme that placed the points, their sampler, and the
// time reading and checking the file took (a table's decoding, a cells file's build).
void set_json(json& j, const fov::pointset& set, double load_ms) {
  j["acuity"] = fov::acuity_model_name(set.model.acuity.model);
  j["sampler"] = fov::label_of(fov::point_sampler_labels, set.darts.sampler);
  j["set_load_ms"] = load_ms;
}

// The viewer's eye a comparison weighs errors with: the set's acuity model (the default one
// without a set) at its true eccentricity on `display`.
fov::spacing_model viewer_eye(const fov::display_geometry& display, const fov::pointset* set) {
  fov::spacing_model eye;
  eye.display = display;
  if (set) eye.acuity = set->model.acuity;
  return eye;
}

// What --compare and --reference-spp measure, as the flags say.
fov::comparison_params comparison_wanted(const render_options& o) {
  fov::comparison_params what;
  what.flip = !o.no_flip, what.jod = !o.no_jod, what.photometry = o.photometry;
  what.keep_maps = !o.flip_map.empty() || !o.foveated_flip_map.empty();
  return what;
}

// A frame's cost as JSON: tracing, reconstruction and TAA (null without it; setup, loading
// and warm-up are reported apart) and its rays, primary and cast by kind.
json cost_json(const fov::frame_timing& t, bool taa) {
  return {{"trace_ms", t.trace_ms},
          {"reconstruct_ms", t.reconstruct_ms},
          {"taa_ms", taa ? json(t.taa_ms) : json(nullptr)},
          {"total_ms", t.total_ms()},
          {"rays", t.rays},
          {"rays_cast", {{"primary", t.cast.primary}, {"shadow", t.cast.shadow}, {"bounce", t.cast.bounce}}}};
}

// The cost and rays of one eye's frame as JSON.
json eye_json(const fov::frame_timing& t, fov::gaze_point gaze, bool taa, bool foveated) {
  json e = cost_json(t, taa);
  e["gaze"] = {gaze.x, gaze.y};
  e["points_traced"] = foveated ? json(t.points_traced) : json(nullptr);
  if (t.reused) e["reuse"] = fov::reuse_json(t.reuse);
  return e;
}

// --stereo: both eyes, each the screen of the set (or of --width/--height, --display with
// --reference), written side by side; per eye its cost, rays and, with --reference-spp, its
// error against its own converged reference with its noise floor.
int render_stereo(const render_options& o, const fov::render_params& p, std::shared_ptr<const fov::scene> scene,
                  std::shared_ptr<const fov::pointset> set, const fov::display_geometry& display, fov::gaze_point gaze_left,
                  fov::gaze_point gaze_right, json j) {
  using fov::eye_side;
  fov::stereo_renderer sr(scene, p);
  // Each eye's own params (its half of a rolling panel) for what is rendered through one eye.
  const fov::render_params pl = fov::stereo_renderer::for_eye(p, eye_side::left), pr = fov::stereo_renderer::for_eye(p, eye_side::right);
  fov::stereo_timing t;
  fov::frame image;
  const int w = display.width, h = display.height;
  if (o.reference) {
    if (!o.no_warmup)
      j["warmup_ms"] = sr.eye(eye_side::left).warm_up_reference(w, h, pl).trace_ms +
                       sr.eye(eye_side::right).warm_up_reference(w, h, pr).trace_ms;
    if (o.taa_frames > 0)
      image = fov::side_by_side(sr.eye(eye_side::left).full_steady_state(display, gaze_left, pl, o.taa_frames, nullptr, &t.left),
                                sr.eye(eye_side::right).full_steady_state(display, gaze_right, pr, o.taa_frames, nullptr, &t.right));
    else
      image = sr.reference(w, h, p, &t);
  } else {
    sr.use_pointset(set);
    if (p.device == fov::reconstruct_device::opencl)
      j["device_setup_ms"] = sr.eye(eye_side::left).device_setup_ms() + sr.eye(eye_side::right).device_setup_ms();
    if (const std::string warn = sr.eye(eye_side::left).device_warning(); !warn.empty()) std::cerr << "fovrender: " << warn << "\n";
    if (!o.no_warmup)
      j["warmup_ms"] = sr.eye(eye_side::left).warm_up(gaze_left, pl).trace_ms + sr.eye(eye_side::right).warm_up(gaze_right, pr).trace_ms;
    for (uint32_t n = 0; n < std::max<uint32_t>(1, o.taa_frames); ++n) image = sr.foveated(gaze_left, gaze_right, p, &t);
    j["device"] = sr.eye(eye_side::left).device();
    j["k"] = p.reconstruct.k;
  }
  if (p.taa) j["taa_frames"] = o.taa_frames, j["pattern"] = fov::label_of(fov::ray_pattern_labels, p.pattern);
  j["stereo"] = true;
  j["ipd_mm"] = p.stereo.ipd_mm;
  j["reuse_mode"] = fov::label_of(fov::reuse_mode_labels, p.reuse.mode);
  json eyes{{"left", eye_json(t.left, gaze_left, p.taa, !o.reference)},
            {"right", eye_json(t.right, gaze_right, p.taa, !o.reference)}};
  std::string compared;
  if (o.reference_spp > 0) {
    const fov::spacing_model eye = viewer_eye(display, set.get());
    const fov::comparison_params what = comparison_wanted(o);
    for (const eye_side e : {eye_side::left, eye_side::right}) {
      const char* name = fov::label_of(fov::eye_side_labels, e);
      const fov::converged_comparison cc = fov::compare_converged(sr.eye(e), fov::eye_half(image, e), eye,
                                                                  e == eye_side::left ? gaze_left : gaze_right,
                                                                  e == eye_side::left ? pl : pr, o.reference_spp, what);
      eyes[name]["metrics"] = fov::comparison_json(cc.against);
      eyes[name]["noise_floor"] = fov::comparison_json(cc.floor);
      eyes[name]["converged_reference_ms"] = cc.reference_ms;
      compared += fmt::format("{} eye: {}\n  noise floor, a second reference {}\n", name,
                              fov::comparison_text(cc.against, fmt::format("a {}-spp converged reference", o.reference_spp)),
                              fov::comparison_text(cc.floor, "the first"));
    }
    j["reference_spp"] = o.reference_spp;
  }
  j["eyes"] = eyes;
  j.update(cost_json(fov::both_eyes(t), p.taa));
  j["width"] = image.width;  // both eyes
  j["height"] = image.height;
  j["eye_width"] = w;
  j["spp"] = p.spp;
  j["method"] = o.reference ? "reference" : fov::method_name(p.reconstruct.how);
  for (const std::string& output : o.outputs) fov::write_frame(image, output);
  if (o.json) {
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{} stereo, two {}x{} eyes: left {} rays, right {} rays{}; trace {:.1f} ms, reconstruct {:.1f} ms\n",
             j["method"].get<std::string>(), w, h, t.left.rays, t.right.rays,
             t.right.reused ? fmt::format(" (kept {} of {} points)", t.right.reuse.reused, t.right.reuse.points) : "",
             j["trace_ms"].get<double>(), j["reconstruct_ms"].get<double>());
  if (!compared.empty()) fmt::print("{}", compared);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  fov::keep_frame_buffers_in_heap();
  CLI::App app{"fovrender: render one frame foveated (or at full resolution) and measure it"};
  render_options o;
  fov::render_params p;
  app.add_option("--scene", o.scene, "builtin, builtin:cornell (a room where bounces matter), a glTF/OBJ file, or env:IMAGE");
  app.add_option("--points", o.points, "Point set (.fovset); gives the screen size");
  app.add_option("--gaze", o.gaze, "X,Y in screen pixels, centre or corner (with --stereo: the left eye's, in its screen)");
  app.add_option("--gaze-right", o.gaze_right, "With --stereo: the right eye's gaze in its screen (default: --gaze)");
  fov::add_render_flags(app, p, fov::flags_all | fov::flags_rolling | fov::flags_reuse | fov::flags_stereo);
  app.add_flag("--reference", o.reference, "Render at full resolution instead");
  app.add_option("--ray-floor", o.ray_floor,
                 "Rays falling with eccentricity from --spp at the gaze to this floor as the acuity model's point density "
                 "falls: with --reference every pixel traced so (a foveated sampling rate), with --points each point "
                 "(the set's own model; a grid fovea's points as the full grid's pixels; docs/tracer.md)")
      ->check(CLI::Range(1u, fov::max_spp));
  app.add_option("--falloff-scale", o.falloff_scale,
                 "With --reference --ray-floor: the acuity model's scale s the full grid's rays follow (1 = the thesis's "
                 "model; a point set's rays follow its own)");
  app.add_option("--level", o.level, "Render this level of a nested set (0 the coarsest) as a fixed set")
      ->check(CLI::Range(0, int(fov::max_levels) - 1));
  app.add_option("--width", o.width, "Screen width without --points")->check(CLI::Range(1, 65536));
  app.add_option("--height", o.height, "Screen height without --points")->check(CLI::Range(1, 65536));
  app.add_option("--display", o.display, "Without --points: " + fov::display_help());
  app.add_option("--taa-frames", o.taa_frames,
                 "Render this many frames of the still view with TAA (--pattern), foveated or --reference (the full grid's "
                 "steady state; docs/pipeline.md)")
      ->check(CLI::Range(0u, 10000u));
  app.add_option("--speedup", o.speedup,
                 "Time N full-resolution frames at the same spp, each right before a foveated frame: JSON speedup "
                 "(median, min, max of the per-pair ratios)")
      ->check(CLI::Range(1u, 1000u));
  app.add_option("--flicker", o.flicker,
                 "Also measure flicker along N frames of a slow turn with a drifting gaze (fov/flicker.h; --flicker-yaw, "
                 "--flicker-shift, --flicker-gaze): the mean frame-to-frame luminance change raw, with TAA (its own rays) "
                 "and at full resolution, in JSON flicker; with --reuse temporal, the path traced fully and with reuse "
                 "(rays, flicker, and with --reference-spp video JOD) in JSON reuse_path")
      ->check(CLI::Range(2u, 1000u));
  app.add_option("--flicker-yaw", o.path.yaw_deg_per_frame, "With --flicker: the camera's turn to the right a frame, degrees")
      ->check(CLI::Range(-10.0f, 10.0f))
      ->capture_default_str();
  app.add_option("--flicker-shift", o.path.shift_per_frame,
                 "With --flicker: the camera's move to the right a frame, world units (parallax: disocclusion)")
      ->check(CLI::Range(-10.0f, 10.0f))
      ->capture_default_str();
  app.add_option("--flicker-gaze", o.path.gaze_px_per_frame, "With --flicker: the gaze's drift to the right a frame, pixels")
      ->check(CLI::Range(-100.0, 100.0))
      ->capture_default_str();
  app.add_flag("--no-warmup", o.no_warmup,
               "Time the very first frame: texture loading, kernel compilation and RBF weights included");
  app.add_option("-o,--output", o.outputs, "Output image (.exr linear, .png sRGB); may be repeated");
  CLI::Option* debug = fov::add_label_option(app, "--debug-view", o.debug, fov::debug_view_labels,
                                               "Write that overlay too (none unless given)", false);
  app.add_option("--debug-output", o.debug_output, "File for the overlay (default: the first -o with '-VIEW' before the extension)");
  app.add_option("--compare", o.compare, "Reference image: print PSNR/SSIM, FLIP and foveated FLIP by eccentricity band");
  app.add_option("--reference-spp", o.reference_spp,
                 "Compare against a converged reference of N Sobol rays per pixel traced here, with its noise floor "
                 "(a second one, another seed) in JSON noise_floor")
      ->check(CLI::Range(1u, fov::max_spp));
  app.add_flag("--no-flip", o.no_flip, "With --compare: skip FLIP and the foveated FLIP (seconds on a large frame)");
  app.add_flag("--no-jod", o.no_jod, "With --compare: skip JOD (FovVideoVDP, a third of a second on a FOVE frame)");
  fov::add_photometry_flags(app, o.photometry);
  app.add_option("--flip-map", o.flip_map, "With --compare: write the FLIP map (grey = 255 x error)");
  app.add_option("--foveated-flip-map", o.foveated_flip_map, "With --compare: write the foveated FLIP map");
  app.add_flag("--json", o.json, "Print JSON");
  return fov::run_tool("fovrender", app, argc, argv, [&] {
    o.debug_asked = debug->count() > 0;
    o.size_given = app.count("--width") + app.count("--height") > 0;
    o.falloff_scale_given = app.count("--falloff-scale") > 0;
    o.path_given = app.count("--flicker-yaw") + app.count("--flicker-shift") + app.count("--flicker-gaze") > 0;
    if (!o.display.empty()) {
      if (!o.points.empty()) throw usage_error("--display: the set gives the display; drop it with --points");
      if (o.size_given) throw usage_error("--display: give it or --width/--height, not both");
      const fov::display_geometry d = fov::require_display("--display", o.display);
      o.width = d.width, o.height = d.height, o.viewing_distance = d.viewing_distance;
    }
    o.photometry_given = app.count("--peak-luminance") + app.count("--contrast") + app.count("--ambient") > 0;
    check_options(o, p);
    p.taa = o.taa_frames > 0;
    if (!o.reference) p.ray_floor = o.ray_floor;
    if (o.debug_asked && o.debug_output.empty()) {
      const std::filesystem::path first(o.outputs.front());
      o.debug_output = (first.parent_path() / (first.stem().string() + "-" + fov::label_of(fov::debug_view_labels, o.debug)))
                           .string() + ".png";
    }
    // Every output before anything is read, rendered or written: a format that can be
    // written, not a directory, link or device, none of the inputs (--compare ref.png -o
    // ref.png would overwrite it) and no two the same; after the scene loads, none of the
    // files it was read from either (its buffers and textures).
    std::vector<std::pair<std::string, std::string>> outputs;  // flag, path
    for (const std::string& out : o.outputs) outputs.emplace_back("-o", out);
    outputs.emplace_back("--debug-output", o.debug_output);
    outputs.emplace_back("--flip-map", o.flip_map);
    outputs.emplace_back("--foveated-flip-map", o.foveated_flip_map);
    const std::vector<std::string> inputs = {o.compare, o.points, o.scene.rfind("env:", 0) == 0 ? o.scene.substr(4) : o.scene};
    for (size_t i = 0; i < outputs.size(); ++i) {
      const auto& [flag, out] = outputs[i];
      if (out.empty()) continue;
      if (const std::string why = fov::image_format_problem(out); !why.empty()) throw usage_error(fmt::format("{} {}: {}", flag, out, why));
      fov::require_output(flag, out, inputs);
      for (size_t j = 0; j < i; ++j)
        if (outputs[j].second == out) throw usage_error(fmt::format("{} {}: also given to {}", flag, out, outputs[j].first));
    }

    fov::require_valid(p);  // what does not depend on the set, before loading it
    std::shared_ptr<const fov::pointset> set;
    fov::display_geometry display{o.width, o.height, o.viewing_distance};
    double set_load_ms = 0;
    if (!o.points.empty()) {
      const auto loading_set = std::chrono::steady_clock::now();
      set = std::make_shared<const fov::pointset>(fov::load_pointset(o.points));
      set_load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - loading_set).count();
      set = fov::select_level(set, o.level, o.points);
      display = set->model.display;
    }
    const std::string problem = fov::validate(p, set.get());
    if (!problem.empty()) throw usage_error(set ? fmt::format("{} for {}", problem, o.points) : problem);
    const fov::gaze_point gaze = fov::require_gaze("--gaze", o.gaze, display);
    const fov::gaze_point gaze_right = o.gaze_right.empty() ? gaze : fov::require_gaze("--gaze-right", o.gaze_right, display);
    // The reference is read and checked before anything is rendered or written.
    fov::frame compare_to;
    if (!o.compare.empty()) {
      compare_to = fov::read_frame(o.compare);
      if (compare_to.width != display.width || compare_to.height != display.height)
        throw usage_error(fmt::format("--compare {}: {}x{} does not match the {}x{} frame", o.compare, compare_to.width,
                                      compare_to.height, display.width, display.height));
    }

    json j;
    j["integrator"] = fov::label_of(fov::integrator_labels, p.method);
    if (p.rolling.path)
      j["camera_time_ms"] = p.rolling.start_ms;
    j["rolling"] = fov::scanout_name(p.rolling.order);
    if (p.rolling.order != fov::scanout::global) j["frame_period_ms"] = p.rolling.frame_period_ms;
    if (p.method == fov::integrator::path) j["bounces"] = p.bounces;
    const auto loading = std::chrono::steady_clock::now();
    std::shared_ptr<const fov::scene> scene = fov::load_scene(o.scene, p.env_light);
    j["scene_load_ms"] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - loading).count();
    for (const auto& [flag, out] : outputs)  // the rest was checked above: only the files the scene was read from
      if (!out.empty())
        if (const std::string why = fov::output_file_problem(out, scene->description().files); !why.empty())
          throw usage_error(fmt::format("{} {}: {}", flag, out, why));
    for (const std::string& w : scene->warnings()) std::cerr << "fovrender: warning: " << w << "\n";
    if (p.stereo.enabled) {
      if (set) set_json(j, *set, set_load_ms);
      return render_stereo(o, p, scene, set, display, gaze, gaze_right, j);
    }
    fov::renderer r(scene, p);
    fov::frame image;
    fov::frame_timing t;
    if (o.reference) {
      if (!o.no_warmup) j["warmup_ms"] = r.warm_up_reference(display.width, display.height, p).trace_ms;
      if (o.ray_floor > 0) {
        fov::ray_falloff f;
        f.model.display = display, f.model.scale = o.falloff_scale, f.gaze = gaze, f.floor = o.ray_floor;
        if (const std::string why = fov::falloff_problem(f, p.spp); !why.empty()) throw usage_error("--ray-floor: " + why);
        image = o.taa_frames ? r.full_steady_state(display, gaze, p, o.taa_frames, &f, &t) : r.falloff_frame(f, p, &t).image;
        j["ray_floor"] = o.ray_floor, j["falloff_scale"] = o.falloff_scale;
      } else {
        image = o.taa_frames ? r.full_steady_state(display, gaze, p, o.taa_frames, nullptr, &t)
                             : r.reference(display.width, display.height, p, &t).image;
      }
      // With --taa-frames N: N frames in the patterns of frames 0..N-1 blended by TAA; the JSON reports the last frame's costs.
      if (p.taa) j["taa_frames"] = o.taa_frames, j["pattern"] = fov::label_of(fov::ray_pattern_labels, p.pattern);
    } else {
      r.use_pointset(set);
      set_json(j, *set, set_load_ms);
      if (p.device == fov::reconstruct_device::opencl) j["device_setup_ms"] = r.device_setup_ms();
      if (r.levels()) {  // the levels' k-NN cells, then those and a reconstructor per coarser level
        j["levels_cells_ms"] = 1e3 * r.levels()->seconds;
        j["levels_setup_ms"] = r.levels_setup_ms();
      }
      if (o.level >= 0) j["level"] = o.level, j["scale"] = set->model.scale;
      if (const std::string w = r.device_warning(); !w.empty()) std::cerr << "fovrender: " << w << "\n";
      if (!o.no_warmup) {
        const fov::warm_up_report w = r.warm_up(gaze, p);
        j["warmup_ms"] = w.trace_ms;
        j["device_first_launch_ms"] = w.reconstruct_ms;
        if (fov::cached_weights_method(p.reconstruct.how)) j["weights_ms"] = w.weights_ms;
        j["traced_index_ms"] = w.traced_index_ms;
      }
      // With --taa-frames N: N frames of the same view blended by TAA; the JSON reports the last frame's costs.
      const fov::frame* last = nullptr;  // the renderer's frame, valid until its next call
      for (uint32_t n = 0; n < std::max<uint32_t>(1, o.taa_frames); ++n) last = &r.foveated(gaze, p, &t);
      image = *last;
      if (o.speedup > 0) {
        if (!o.no_warmup) r.warm_up_reference(display.width, display.height, p);
        const fov::paired_timing st = fov::measure_speedup(r, gaze, p, display.width, display.height, o.speedup);
        j["speedup"] = st.speedup.median, j["speedup_lo"] = st.speedup.min, j["speedup_hi"] = st.speedup.max;
        j["full_ms"] = st.full_ms.median, j["full_ms_lo"] = st.full_ms.min, j["full_ms_hi"] = st.full_ms.max;
        j["frame_ms"] = st.frame_ms.median, j["frame_ms_lo"] = st.frame_ms.min, j["frame_ms_hi"] = st.frame_ms.max;
        j["speedup_pairs"] = o.speedup;
        const fov::speedup_interval iv = fov::chained_speedup(st.ratios);  // 95 % bootstrap interval of the median
        j["speedup_interval"] = {iv.lo, iv.hi};
      }
      if (t.reused) j["reuse"] = fov::reuse_json(t.reuse);
      if (o.flicker > 0 && p.reuse.mode == fov::reuse_mode::temporal) {
        // The path traced fully and with reuse; with --reference-spp, each sequence's video JOD
        // against converged frames along it, and their noise floor (a second seed).
        fov::flicker_params fp = o.path;
        fp.frames = o.flicker;
        const fov::frame_timing last = t;
        std::vector<fov::frame> converged;
        json floor = nullptr;
        if (o.reference_spp > 0) {
          const auto [first, second] = fov::converged_seeds(p.seed);
          converged = fov::converged_path(r, p, o.reference_spp, first, fp);
          floor = fov::converged_path_floor(fov::converged_path(r, p, o.reference_spp, second, fp), converged, gaze, display, fp).jod;
        }
        const fov::reuse_path_report rp = fov::measure_reuse(r, gaze, p, fp, converged);
        t = last;
        j["reuse_path"] = reuse_path_json(rp, fp);
        if (o.reference_spp > 0) j["reuse_path"]["jod_floor"] = floor;
      } else if (o.flicker > 0) {
        fov::flicker_params fp = o.path;
        fp.frames = o.flicker;
        fp.taa_own_rays = true;  // what a viewer of TAA sees
        const fov::frame_timing last = t;
        const fov::flicker_report fl = fov::measure_flicker(r, gaze, p, fp);
        t = last;
        j["flicker"] = {{"frames", o.flicker}, {"raw", fl.raw}, {"taa", fl.taa}, {"full_resolution", fl.reference}};
      }
      j["device"] = r.device();
      if (p.reconstruct.how == fov::method::rbf) {
        j["rbf"] = {{"kernel", fov::label_of(fov::rbf_kernel_labels, p.reconstruct.kernel)}, {"shape", p.reconstruct.shape},
                    {"pixels", t.weights.pixels}, {"fallbacks", t.weights.fallbacks},
                    {"fallback_near_duplicates", t.weights.near_duplicates}, {"fallback_singular", t.weights.singular},
                    {"fallback_weight_sum", t.weights.weight_sum}, {"max_weight_sum", fov::rbf_max_weight_sum},
                    {"worst_weight_sum", t.weights.worst_weight_sum}, {"worst_condition", t.weights.worst_condition},
                    {"condition_sampled_pixels", t.weights.sampled}};
      } else if (fov::delaunay_method(p.reconstruct.how)) {
        j["delaunay"] = {{"pixels", t.weights.pixels}, {"fallbacks", t.weights.fallbacks},
                         {"fallback_outside_hull", t.weights.outside_hull}, {"fallback_beyond_k", t.weights.beyond_k}};
      }
      if (const std::string w = fov::weight_fallback_warning(t.weights, p.reconstruct.how); !w.empty())
        std::cerr << "fovrender: " << w << "\n";
      if (p.taa) j["taa_frames"] = o.taa_frames, j["pattern"] = fov::label_of(fov::ray_pattern_labels, p.pattern);
      j["k"] = p.reconstruct.k;
      if (t.adaptive) {
        j["adaptive"] = fov::refinement_json(t, p, *r.levels());
        if (const std::string w = fov::refinement_warning(t, p); !w.empty()) std::cerr << "fovrender: " << w << "\n";
      }
      if (p.ray_floor > 0) j["ray_floor"] = p.ray_floor;
      j["texture_footprint"] = fov::texture_footprint_name(p.footprint);
    }
    j.update(cost_json(t, p.taa));
    j["points_traced"] = o.reference ? json(nullptr) : json(t.points_traced);
    j["width"] = display.width;
    j["height"] = display.height;
    j["spp"] = p.spp;
    j["method"] = o.reference ? (o.ray_floor > 0 ? "falloff" : "reference") : fov::method_name(p.reconstruct.how);

    for (const std::string& output : o.outputs) fov::write_frame(image, output);
    if (o.debug_asked) {
      fov::write_frame(fov::debug_overlay(o.debug, image, o.reference ? nullptr : set.get(), gaze, r.last_refinement(),
                                          r.levels() ? uint32_t(r.levels()->levels.size()) : 1),
                       o.debug_output);
    }
    std::string compared;
    if (!o.compare.empty() || o.reference_spp > 0) {
      const fov::spacing_model eye = viewer_eye(display, set.get());
      const fov::comparison_params what = comparison_wanted(o);
      fov::comparison c;
      if (o.reference_spp > 0) {
        const fov::converged_comparison cc = fov::compare_converged(r, image, eye, gaze, p, o.reference_spp, what);
        c = cc.against;
        j["noise_floor"] = fov::comparison_json(cc.floor);
        j["reference_spp"] = o.reference_spp;
        j["converged_reference_ms"] = cc.reference_ms;
        compared = fov::comparison_text(c, fmt::format("a {}-spp converged reference", o.reference_spp)) +
                   "\nnoise floor, a second reference " + fov::comparison_text(cc.floor, "the first");
      } else {
        c = fov::compare_images(image, compare_to, eye, gaze, what);
        compared = fov::comparison_text(c, o.compare);
      }
      j["metrics"] = fov::comparison_json(c);
      if (!o.flip_map.empty()) fov::write_error_map(c.flip.flip_map, o.flip_map);
      if (!o.foveated_flip_map.empty()) fov::write_error_map(c.flip.foveated_map, o.foveated_flip_map);
    }
    if (o.json) {
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    fmt::print("{} {}x{}: {} rays, trace {:.1f} ms, reconstruct {:.1f} ms\n", j["method"].get<std::string>(), display.width,
               display.height, t.rays, t.trace_ms, t.reconstruct_ms);
    if (j.contains("speedup"))
      fmt::print("speedup over full resolution at {} spp: {:.2f}x (95 % interval {:.2f}-{:.2f}; min {:.2f}, max {:.2f} over {} pairs; "
                 "full {:.1f} ms, foveated {:.1f} ms)\n",
                 p.spp, j["speedup"].get<double>(), j["speedup_interval"][0].get<double>(), j["speedup_interval"][1].get<double>(),
                 j["speedup_lo"].get<double>(), j["speedup_hi"].get<double>(), o.speedup, j["full_ms"].get<double>(),
                 j["frame_ms"].get<double>());
    if (!compared.empty()) fmt::print("{}\n", compared);
    return 0;
  });
}
