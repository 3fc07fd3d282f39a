#include "viewer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../common/cli.h"
#include "../common/debug_views.h"
#include "../common/gaze_flags.h"
#include "../common/gaze_log.h"
#include "../common/gaze_source.h"
#include "../common/image_io.h"
#include "../common/render_flags.h"
#include "../common/window.h"
#include "camera_path.h"
#include "fov/camera.h"
#include "fov/comparison.h"
#include "fov/files.h"
#include "fov/pointset_io.h"
#include "fov/renderer.h"
#include "fov/stereo_renderer.h"
#include "fov/scene.h"

namespace {

using json = nlohmann::json;
using fov::usage_error;
namespace fs = std::filesystem;
using clock_type = std::chrono::steady_clock;

double ms_between(clock_type::time_point a, clock_type::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// The point sets the viewer can switch between, by scale; loaded on first use.
struct pointset_family {
  std::vector<std::pair<double, std::string>> files;  // scale, path; ascending
  std::map<std::string, std::shared_ptr<const fov::pointset>> loaded;
  std::shared_ptr<const fov::pointset> get(size_t i) {
    auto& slot = loaded[files[i].second];
    if (!slot) {
      if (loaded.size() > 3) {  // keep memory bounded: a FOVE table is 0.6 GB
        for (auto it = loaded.begin(); it != loaded.end(); ++it)
          if (it->first != files[i].second) { loaded.erase(it); break; }
      }
      auto& fresh = loaded[files[i].second];
      fresh = std::make_shared<const fov::pointset>(fov::load_pointset(files[i].second));
      return fresh;
    }
    return slot;
  }
};

// The sets of one display and fovea in --points-dir, by scale. A directory may hold several
// displays' families (pick one with --display) and a display's darts and grid sets (the
// darts family is shown; a grid set with --points). With --scale, only families holding it.
pointset_family find_family(const std::string& points, const std::string& dir, const std::string& display_spec, double scale) {
  pointset_family f;
  if (!points.empty()) {
    const fov::pointset head = fov::load_pointset(points, {false});
    f.files.emplace_back(head.model.scale, points);
    return f;
  }
  if (!fs::is_directory(dir)) throw std::runtime_error(fmt::format("--points-dir {}: not a directory", dir));
  std::string wanted;
  if (!display_spec.empty()) wanted = fov::display_name(fov::require_display("--display", display_spec));
  std::map<std::pair<std::string, std::string>, pointset_family> families;  // (display, fovea)
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".fovset") continue;
    const fov::pointset head = fov::load_pointset(e.path().string(), {false});
    const std::string name = fov::display_name(head.model.display);
    if (!wanted.empty() && name != wanted) continue;
    families[{name, fov::fovea_label(head.darts)}].files.emplace_back(head.model.scale, e.path().string());
  }
  for (auto it = families.begin(); it != families.end();) {
    const bool has = scale <= 0 || std::any_of(it->second.files.begin(), it->second.files.end(),
                                               [&](const auto& file) { return std::fabs(file.first - scale) <= 1e-6; });
    it = has ? std::next(it) : families.erase(it);
  }
  const std::string what = fmt::format("{}{}", scale > 0 ? fmt::format(" at s = {}", scale) : "",
                                       wanted.empty() ? "" : " for display " + wanted);
  if (families.empty()) {
    if (scale > 0) throw usage_error(fmt::format("--scale {}: no such set in {}{}", scale, dir, what));
    throw std::runtime_error(fmt::format("--points-dir {}: no .fovset files{}", dir, what));
  }
  std::set<std::string> displays;
  for (const auto& [key, family] : families) displays.insert(key.first);
  if (displays.size() > 1) {
    std::string list;
    for (const std::string& d : displays) list += (list.empty() ? "" : ", ") + d;
    throw usage_error(fmt::format("--points-dir {} holds sets{} of several displays ({}): choose one with --display", dir, what, list));
  }
  // One display: its darts family, else its only family.
  auto chosen = families.find({*displays.begin(), "darts"});
  if (chosen == families.end()) {
    if (families.size() > 1)
      throw usage_error(fmt::format("--points-dir {} holds several grid families{}: open one set with --points", dir, what));
    chosen = families.begin();
  }
  f = chosen->second;
  std::sort(f.files.begin(), f.files.end());
  return f;
}

const char* help_lines[] = {
    "1-5    nearest neighbour / Shepard / RBF / barycentric / natural", "+/-    k",  "[ ]    previous / next point-set scale",
    "T      TAA on/off",  "R      full-resolution reference", "V      debug view: points, density, eccentricity, error",
    "G      gaze cursor", "P      screenshot (PNG + JSON); also S while the mouse is the gaze",
    "WASD   move, right-drag turns (when the mouse is not the gaze)",
    "H      this help",   "Q/Esc  quit"};

}  // namespace

namespace fov {

int run_viewer(const viewer_options& o, render_params settings) {
  const std::string& scene_spec = o.scene;
  const std::string &points = o.points, &points_dir = o.points_dir;
  const std::string &camera_path_file = o.camera_path, &fixed_gaze = o.fixed_gaze, &screenshot_dir = o.screenshot_dir;
  const std::string& compare = o.compare;
  const double scale = o.scale, target_fps = o.target_fps;
  const uint32_t frames = o.frames;
  const long shot_frame = o.screenshot_frame;
  const std::string& shot_file = o.screenshot_file;
  const bool as_json = o.json, pipeline = o.pipeline, no_taa = o.no_taa;
  pointset_family family = find_family(points, points_dir, o.display, scale);
  size_t level = 0;
  if (scale > 0) {
    while (level + 1 < family.files.size() && family.files[level].first + 1e-6 < scale) ++level;
    if (std::fabs(family.files[level].first - scale) > 1e-6)
      throw usage_error(fmt::format("--scale {}: no such set in {}", scale, points_dir));
  }
  std::shared_ptr<const fov::pointset> set = family.get(level);
  const fov::display_geometry display = set->model.display;
  fov::require_valid(settings, set.get());
  settings.taa = !no_taa;
  const uint32_t spp = settings.spp;
  const int w = display.width, h = display.height;

  std::shared_ptr<const fov::scene> scn = fov::load_scene(scene_spec, settings.env_light);
  for (const std::string& warning : scn->warnings()) std::cerr << "fovview: warning: " << warning << "\n";
  std::optional<fov::camera_path> path;
  if (!camera_path_file.empty()) path = fov::load_camera_path(camera_path_file);
  fov::frame reference_image;
  if (!compare.empty()) {
    reference_image = fov::read_frame(compare);
    if (reference_image.width != w || reference_image.height != h)
      throw usage_error(fmt::format("--compare {}: {}x{} is not the {}x{} screen", compare, reference_image.width,
                                    reference_image.height, w, h));
  }

  std::unique_ptr<fov::gaze_source> gaze = fov::open_gaze(o.gaze, w, h);
  fov::mouse_gaze* mouse = nullptr;
  if (!gaze && !fixed_gaze.empty()) {
    const fov::gaze_point at = fov::require_gaze("--gaze", fixed_gaze, display);
    gaze = fov::fixed_gaze(w, h, at.x, at.y);
  } else if (!gaze) {
    auto m = std::make_unique<fov::mouse_gaze>(w, h);
    mouse = m.get();
    gaze = std::move(m);
  }
  fov::gaze_conditioner conditioner(o.gaze.conditioning, display, gaze->live());
  std::string gaze_log = fov::gaze_log_header();
  // A replay gives frame i the gaze, state and read time of the log's row i.
  const std::vector<fov::gaze_log_row> replay = o.gaze_replay.empty() ? std::vector<fov::gaze_log_row>{}
                                                                         : fov::read_gaze_log(o.gaze_replay);
  size_t replay_next = 0;
  const std::string gaze_name = o.gaze_replay.empty() ? gaze->name() : "replay " + o.gaze_replay;
  // A replay runs its log's frames (or --frames of them, if fewer).
  const uint64_t last_frame = replay.empty() ? frames : frames ? std::min<uint64_t>(frames, replay.size()) : replay.size();
  size_t safe_from_level = SIZE_MAX;  // the set's level before the safe mode switched to the densest

  // Two eyes (--stereo): both shown side by side, each at the gaze in its own screen; the
  // keys and a camera path move the head, and the left eye's renderer answers for both where
  // one answer does (the set, the device, the levels).
  const bool two_eyes = settings.stereo.enabled;
  std::optional<fov::stereo_renderer> stereo;
  std::optional<fov::renderer> mono;
  if (two_eyes)
    stereo.emplace(scn, settings);
  else
    mono.emplace(scn, settings);
  fov::renderer& renderer = two_eyes ? stereo->eye(fov::eye_side::left) : *mono;
  fov::camera head = two_eyes ? stereo->head() : fov::camera{};
  auto view_cam = [&]() -> fov::camera& { return two_eyes ? head : renderer.cam(); };
  auto use_set = [&](std::shared_ptr<const fov::pointset> s) {
    if (two_eyes)
      stereo->use_pointset(std::move(s));
    else
      renderer.use_pointset(std::move(s));
  };
  use_set(set);
  if (const std::string warning = renderer.device_warning(); !warning.empty()) std::cerr << "fovview: " << warning << "\n";
  fov::view_window window("fovview", two_eyes ? 2 * w : w, h);
  bool show_reference = false, show_cursor = true, show_help = false;
  // The debug views draw one eye's screen: not offered with two eyes.
  std::vector<std::string> views = two_eyes ? std::vector<std::string>{""}
                                            : std::vector<std::string>{"", "points", "density", "eccentricity", "error"};
  if (settings.adaptive.enabled && !two_eyes) views.push_back("refinement");
  size_t view = 0;
  uint64_t rbf_fallbacks_said = 0;  // RBF pixels that fell back to Shepard, as last said
  bool budget_warned = false;  // --adaptive-budget below the coarsest level: said once
  fov::frame error_reference;  // the full-resolution frame the error view compares with
  fov::camera error_reference_cam;
  const auto start = clock_type::now();
  double fps = 0, display_ms = 0, latency_ms = 0;
  uint64_t screenshots = 0;
  std::string status;  // one-line messages (screenshot saved, silent tracker)
  struct frame_stats {
    double frame, trace, reconstruct, taa, display, latency, gaze_age;
    uint32_t spp;
    double rays, refined;  // rays traced; an adaptive frame's points refined beyond the coarsest level
    bool budget_short;
    double reused_share;  // temporal reuse: the share of the points that kept a sample
  };
  std::vector<frame_stats> history;
  // What a frame shows: the gaze and camera when they were read. With pipelining the next
  // frame's are read (and its trace started) before this frame is shown.
  struct frame_inputs {
    fov::gaze_point gaze;
    double poll_ms;
    fov::camera cam;
    fov::gaze_estimate estimate;
    double sample_local_ms;  // the newest sample's time from the start (NaN: none yet)
  };
  std::vector<fov::gaze_sample> fresh;
  double clock_at_start = 0;
  auto read_inputs = [&](const fov::camera& current) {
    if (!replay.empty()) {
      const fov::gaze_log_row& r = replay[std::min(replay_next++, replay.size() - 1)];
      return frame_inputs{r.estimate.at, r.local_ms, path ? path->at(r.local_ms, current) : current, r.estimate, r.sample_local_ms};
    }
    const double now_ms = ms_between(start, clock_type::now());
    if (mouse) {
      double x, y;
      if (window.mouse(x, y)) mouse->set(two_eyes && x >= w ? x - w : x, y);  // either eye's screen
    }
    fresh.clear();
    const double clock_ms = fov::gaze_clock_ms();
    gaze->read(clock_ms, fresh);
    const fov::gaze_estimate e = conditioner.update(clock_ms, fresh);
    frame_inputs in{e.at, now_ms, path ? path->at(now_ms, current) : current, e,
                    e.has_sample ? e.newest.t_ms - clock_at_start : NAN};
    return in;
  };
  clock_at_start = fov::gaze_clock_ms() - ms_between(start, clock_type::now());
  std::optional<frame_inputs> next;  // read ahead, with its trace under way

  for (uint64_t frame_index = 0; last_frame == 0 || frame_index < last_frame; ++frame_index) {
    const auto frame_start = clock_type::now();
    const double now_ms = ms_between(start, frame_start);
    const frame_inputs in = next ? *next : read_inputs(view_cam());
    next.reset();
    const fov::gaze_point g = in.gaze;
    const fov::gaze_estimate& ge = in.estimate;
    if (path) view_cam() = in.cam;
    // A saccade landed: the TAA history counts as seen from where it began, so the new
    // fovea takes the current frame (taa_params::focus_lag_deg).
    if (ge.landed) {
      renderer.history_gaze(ge.saccade_onset);
      if (two_eyes) stereo->eye(fov::eye_side::right).history_gaze(ge.saccade_onset);
    }
    // The safe mode renders the densest set (the smallest scale) until the gaze returns.
    if (ge.state == fov::gaze_state::safe && ge.has_sample && safe_from_level == SIZE_MAX && level > 0) {
      safe_from_level = level, level = 0;
      use_set(family.get(level));
    } else if (ge.state != fov::gaze_state::safe && safe_from_level != SIZE_MAX) {
      level = safe_from_level, safe_from_level = SIZE_MAX;
      use_set(family.get(level));
    }

    fov::frame_timing timing;
    fov::stereo_timing eyes;
    fov::frame reference_frame;
    if (two_eyes) stereo->set_head(head);
    const fov::frame& image =
        two_eyes ? (show_reference ? (reference_frame = stereo->reference(w, h, settings, &eyes)) : stereo->foveated(g, g, settings, &eyes))
        : show_reference ? (reference_frame = renderer.reference(w, h, settings, &timing).image)
                         : renderer.foveated(g, settings, &timing);
    if (two_eyes) timing = fov::both_eyes(eyes);
    if (pipeline && !show_reference) {  // the next frame traces while this one is shown
      next = read_inputs(renderer.cam());
      renderer.begin_trace(next->gaze, next->cam, settings);
    }
    const std::string& v = views[view];
    fov::frame overlay;  // only the debug views draw into a copy
    const fov::frame* shown = &image;
    if (v == "error") {
      overlay = image;
      shown = &overlay;
      const fov::camera& c = renderer.cam();
      if (error_reference.rgb.empty() || !fov::same_view(c, error_reference_cam)) {
        fov::render_params at_least_4 = settings;
        at_least_4.spp = std::max<uint32_t>(settings.spp, 4);
        error_reference = renderer.reference(w, h, at_least_4).image;
        error_reference_cam = c;
      }
      for (size_t i = 0; i < overlay.rgb.size(); ++i) {  // |error| x 4, grey scale
        const glm::vec3 d = glm::abs(image.rgb[i] - error_reference.rgb[i]);
        overlay.rgb[i] = glm::vec3(std::min(1.0f, 4.0f * (d.r + d.g + d.b) / 3.0f));
      }
    } else if (fov::debug_view dv; fov::parse_label(fov::debug_view_labels, v, dv)) {
      if (dv == fov::debug_view::refinement && show_reference) dv = fov::debug_view::eccentricity;  // no map for the reference
      overlay = fov::debug_overlay(dv, image, show_reference ? nullptr : renderer.current_set(), g, renderer.last_refinement(),
                                   renderer.levels() ? uint32_t(renderer.levels()->levels.size()) : 1);
      shown = &overlay;
    }
    const auto display_start = clock_type::now();
    cv::Mat bgr = fov::display_image(*shown);
    if (show_cursor) fov::draw_gaze_cursor(bgr, g);
    if (show_cursor && two_eyes) fov::draw_gaze_cursor(bgr, {g.x + w, g.y});
    std::vector<std::string> lines = {
        fmt::format("{:.1f} fps  trace {:.1f}{}  reconstruct {:.1f}  TAA {:.1f}  display {:.1f}  gaze-to-screen {:.1f} ms",
                    fps, timing.trace_ms, timing.traced_ahead ? " (ahead)" : "", timing.reconstruct_ms, timing.taa_ms,
                    display_ms, latency_ms),
        show_reference ? fmt::format("REFERENCE {}x{}, {} rays/frame", w, h, timing.rays)
                       : fmt::format("{} k={} s={:.2f} spp={} TAA {}  {} points, {} rays/frame",
                                     fov::method_name(settings.reconstruct.how), settings.reconstruct.k,
                                     renderer.current_set()->model.scale, settings.spp, settings.taa ? "on" : "off",
                                     timing.points_traced, timing.rays) +
                           (timing.adaptive ? fmt::format("  adaptive: {} refined", timing.refinement.points_refined) : "") +
                           (timing.reused ? fmt::format("  reuse: {} kept ({:.0f} %), {} rays kept", timing.reuse.reused,
                                                        100 * timing.reuse.reused_share(), timing.reuse.rays_reused)
                                          : ""),
        fmt::format("gaze {} ({:.0f}, {:.0f}) {}{}  view {}  device {}", gaze_name, g.x, g.y,
                    fov::label_of(fov::gaze_state_labels, ge.state),
                    ge.has_sample ? fmt::format(" age {:.0f} ms conf {:.2f}", ge.age_ms, ge.newest.confidence) : "",
                    v.empty() ? "frame" : v, timing.on_device ? "OpenCL" : "C++")};
    if (two_eyes)
      lines.push_back(fmt::format("two eyes, IPD {:g} mm: left {} rays, right {} rays{}", settings.stereo.ipd_mm, eyes.left.rays,
                                  eyes.right.rays,
                                  eyes.right.reused ? fmt::format(" (kept {} of {} points from the left)", eyes.right.reuse.reused,
                                                                  eyes.right.reuse.points)
                                                    : ""));
    if (gaze->malformed || gaze->clamped || conditioner.low_confidence || conditioner.dropouts || gaze->clock_jumps)
      lines.push_back(fmt::format("gaze: {} malformed  {} clamped  {} low confidence  {} dropouts  {} clock jumps{}",
                                  gaze->malformed, gaze->clamped, conditioner.low_confidence, conditioner.dropouts,
                                  gaze->clock_jumps, gaze->last_problem.empty() ? "" : "  last: " + gaze->last_problem));
    if (ge.state == fov::gaze_state::safe)
      lines.push_back(ge.has_sample ? "WARNING: no gaze; safe mode (centre, densest set)" : "WARNING: no gaze yet; centre");
    if (!status.empty()) lines.push_back(status);
    if (show_help) lines.insert(lines.end(), std::begin(help_lines), std::end(help_lines));
    else lines.push_back("H: help");
    fov::draw_overlay(bgr, lines, g);
    window.show(bgr);
    const double shown_ms = ms_between(start, clock_type::now());
    latency_ms = shown_ms - in.poll_ms;
    const double gaze_age_ms = ge.has_sample ? fov::gaze_clock_ms() - ge.newest.t_ms : NAN;  // sample to photons, less the panel
    if (!o.gaze_log.empty()) gaze_log += fov::gaze_log_line({frame_index, in.poll_ms, ge, in.sample_local_ms, shown_ms});

    auto save_screenshot = [&](const std::string& file) {
      fov::write_frame(image, file);  // the clean frame: no overlay, no cursor
      const fov::camera& cam = view_cam();  // with two eyes, the head's
      const fov::camera_frame view = fov::make_frame(cam, w, h);
      json j = {{"frame", frame_index},
                {"time_ms", now_ms},
                {"scene", scene_spec},
                {"pointset", family.files[level].second},
                {"scale", renderer.current_set()->model.scale},
                {"method", show_reference ? "reference" : fov::method_name(settings.reconstruct.how)},
                {"k", settings.reconstruct.k},
                {"spp", settings.spp},
                {"taa", settings.taa},
                {"gaze", {g.x, g.y}},
                {"gaze_source", gaze->name()},
                {"camera", {{"position", {cam.position.x, cam.position.y, cam.position.z}},
                            {"forward", {cam.forward.x, cam.forward.y, cam.forward.z}},
                            {"up", {cam.up.x, cam.up.y, cam.up.z}},
                            {"hfov_deg", 2 * glm::degrees(std::atan(view.half_width))},
                            {"vfov_deg", 2 * glm::degrees(std::atan(view.half_height))},
                            {"fov_given", cam.vfov_deg > 0 ? "vertical" : "horizontal"}}},
                {"view", v.empty() ? "frame" : v},
                {"trace_ms", timing.trace_ms},
                {"reconstruct_ms", timing.reconstruct_ms},
                {"taa_ms", timing.taa_ms},
                {"rays", timing.rays},
                {"points_traced", timing.points_traced}};
      if (timing.reused) j["reuse"] = fov::reuse_json(timing.reuse);
      if (two_eyes) {  // the image holds both eyes side by side
        j["stereo"] = true, j["ipd_mm"] = settings.stereo.ipd_mm, j["eye_width"] = w;
        j["eyes"] = {{"left", {{"rays", eyes.left.rays}, {"points_traced", eyes.left.points_traced}}},
                     {"right", {{"rays", eyes.right.rays}, {"points_traced", eyes.right.points_traced}}}};
      }
      if (!reference_image.rgb.empty()) {
        // The schema every tool writes (fovrender --compare's "metrics"); PSNR/SSIM only: FLIP
        // takes seconds on a large frame, JOD a third of one, and a screenshot is taken live.
        fov::spacing_model eye;
        eye.display = display;
        fov::comparison_params psnr_only;
        psnr_only.flip = psnr_only.jod = false;
        j["metrics"] = fov::comparison_json(fov::compare_images(image, reference_image, eye, g, psnr_only));
      }
      const std::string text = j.dump(2) + "\n";
      fov::write_file_atomic(file + ".json", text.data(), text.size());
      status = "saved " + file;
    };
    if (long(frame_index) == shot_frame) save_screenshot(shot_file);

    const int key = window.key(1);
    display_ms = ms_between(display_start, clock_type::now());
    if (window.closed()) break;
    const int c = key >= 0 && key < 256 ? std::tolower(key) : -1;
    if (c == 'q' || key == 27) break;
    if (c >= '1' && c <= '5') {
      constexpr fov::method keys[] = {fov::method::nn, fov::method::shepard, fov::method::rbf, fov::method::barycentric,
                                      fov::method::natural};
      settings.reconstruct.how = keys[c - '1'];
      if (fov::cached_weights_method(settings.reconstruct.how))
        status = fmt::format("{}: computing weights once for the screen (seconds)", fov::method_name(settings.reconstruct.how));
    }
    if (c == '+' || c == '=') settings.reconstruct.k = std::min(settings.reconstruct.k + 1, stored_k(*renderer.current_set()));
    if (c == '-') settings.reconstruct.k = std::max(settings.reconstruct.k - 1, 1u);
    if ((c == '[' && level > 0) || (c == ']' && level + 1 < family.files.size())) {
      level += c == ']' ? 1 : -1;
      use_set(family.get(level));
      settings.reconstruct.k = std::min(settings.reconstruct.k, stored_k(*renderer.current_set()));
    }
    if (c == 't') settings.taa = !settings.taa;
    if (c == 'r') show_reference = !show_reference;
    if (c == 'v') view = (view + 1) % views.size();
    if (c == 'g') show_cursor = !show_cursor;
    if (c == 'h') show_help = !show_help;
    if (c == 'p' || (c == 's' && mouse))
      save_screenshot((fs::path(screenshot_dir) / fmt::format("fovview-{:04d}.png", screenshots++)).string());
    // Camera: WASD moves, right-drag turns, while the mouse is not the gaze (and no path plays).
    fov::camera& cc = view_cam();
    const glm::vec3 right = glm::normalize(glm::cross(cc.forward, cc.up));
    const float step = 0.1f;
    const bool free_camera = !mouse && !path;
    if (free_camera && c == 'w') cc.position += step * cc.forward;
    if (free_camera && c == 's') cc.position -= step * cc.forward;
    if (free_camera && c == 'a') cc.position -= step * right;
    if (free_camera && c == 'd') cc.position += step * right;
    double dx = 0, dy = 0;
    const bool dragged = window.right_drag(dx, dy);  // drained every frame
    if (free_camera && dragged) {
      const float yaw = float(-dx) * 0.004f, pitch = float(-dy) * 0.004f;
      glm::vec3 f = cc.forward * std::cos(yaw) + right * std::sin(yaw);
      f = glm::normalize(f * std::cos(pitch) + cc.up * std::sin(pitch));
      cc.forward = f;
    }
    // Rays per point follow --target-fps: halve when over budget, add one when well under.
    const double frame_ms = ms_between(frame_start, clock_type::now());
    history.push_back({frame_ms, timing.trace_ms, timing.reconstruct_ms, timing.taa_ms, display_ms, latency_ms, gaze_age_ms,
                       settings.spp, double(timing.rays), double(timing.refinement.points_refined),
                       timing.adaptive && timing.refinement.budget_short, timing.reuse.reused_share()});
    // Cached weights' fallbacks: said when their count changes (new weights, another method, k or shape).
    if (timing.weights.fallbacks != rbf_fallbacks_said) {
      if (timing.weights.fallbacks > 0) std::cerr << "fovview: " << fov::weight_fallback_warning(timing.weights, settings.reconstruct.how) << "\n";
      rbf_fallbacks_said = timing.weights.fallbacks;
    }
    if (timing.adaptive && timing.refinement.budget_short && !budget_warned) {
      std::cerr << "fovview: " << fov::refinement_warning(timing, settings) << "\n";
      budget_warned = true;
    }
    fps = fps == 0 ? 1000 / frame_ms : 0.9 * fps + 0.1 * (1000 / frame_ms);
    if (target_fps > 0 && !show_reference) {
      const double budget = 1000 / target_fps;
      if (frame_ms > 1.15 * budget && settings.spp > 1) settings.spp = std::max(1u, settings.spp / 2);
      else if (frame_ms < 0.6 * budget && settings.spp < spp) ++settings.spp;
    }
  }
  if (as_json) {
    const size_t skip = std::min<size_t>(5, history.size() / 2);
    // Percentiles by the nearest rank over the measured frames (NaN values left out).
    auto stats = [&](auto field) {
      std::vector<double> v;
      for (size_t i = skip; i < history.size(); ++i)
        if (const double x = field(history[i]); std::isfinite(x)) v.push_back(x);
      json out = {{"median", nullptr}, {"p95", nullptr}, {"p99", nullptr}, {"max", nullptr}};
      if (v.empty()) return out;
      std::sort(v.begin(), v.end());
      auto rank = [&](double q) { return v[std::min(v.size() - 1, size_t(std::ceil(q * double(v.size()))) - (q > 0))]; };
      out = {{"median", v[v.size() / 2]}, {"p95", rank(0.95)}, {"p99", rank(0.99)}, {"max", v.back()}};
      return out;
    };
    auto median = [&](auto field) {
      const json m = stats(field)["median"];
      return m.is_null() ? 0.0 : m.get<double>();
    };
    const double frame_ms = median([](const frame_stats& f) { return f.frame; });
    // Dropped frames: those that took longer than the target rate's frame period (a frame
    // that takes 2.5 periods drops 2 refreshes); only with --target-fps.
    json dropped = nullptr;
    if (target_fps > 0) {
      uint64_t late = 0, refreshes = 0;
      for (size_t i = skip; i < history.size(); ++i) {
        const double periods = history[i].frame * target_fps / 1000;
        if (periods > 1) ++late, refreshes += uint64_t(std::ceil(periods)) - 1;
      }
      dropped = {{"target_fps", target_fps}, {"late_frames", late}, {"missed_refreshes", refreshes}};
    }
    json j = {{"frames", history.size()},
              {"measured_frames", history.size() - skip},
              {"width", w},
              {"height", h},
              {"scene", scene_spec},
              {"method", fov::method_name(settings.reconstruct.how)},
              {"k", settings.reconstruct.k},
              {"taa", settings.taa},
              {"spp_last", settings.spp},
              {"device", renderer.device()},
              {"frame_ms", frame_ms},
              {"fps", frame_ms > 0 ? 1000 / frame_ms : 0},
              {"trace_ms", median([](const frame_stats& f) { return f.trace; })},
              {"reconstruct_ms", median([](const frame_stats& f) { return f.reconstruct; })},
              {"taa_ms", median([](const frame_stats& f) { return f.taa; })},
              {"display_ms", median([](const frame_stats& f) { return f.display; })},
              {"latency_ms", median([](const frame_stats& f) { return f.latency; })},
              {"distribution_ms",
               {{"frame", stats([](const frame_stats& f) { return f.frame; })},
                {"trace", stats([](const frame_stats& f) { return f.trace; })},
                {"reconstruct", stats([](const frame_stats& f) { return f.reconstruct; })},
                {"taa", stats([](const frame_stats& f) { return f.taa; })},
                {"latency", stats([](const frame_stats& f) { return f.latency; })},
                {"gaze_age", stats([](const frame_stats& f) { return f.gaze_age; })}}},
              {"dropped", dropped},
              {"gaze",
               {{"source", gaze_name},
                {"samples", gaze->samples},
                {"malformed", gaze->malformed},
                {"clamped", gaze->clamped},
                {"clock_jumps", gaze->clock_jumps},
                {"low_confidence", conditioner.low_confidence},
                {"saccades", conditioner.saccades},
                {"dropouts", conditioner.dropouts},
                {"safe_ms", conditioner.safe_ms}}},
              {"pipelined", pipeline}};
    j["rays"] = stats([](const frame_stats& f) { return f.rays; });  // both eyes' with --stereo
    j["stereo"] = two_eyes;
    if (two_eyes) j["ipd_mm"] = settings.stereo.ipd_mm;
    if (settings.adaptive.enabled) {
      uint64_t short_frames = 0;
      for (const frame_stats& f : history) short_frames += f.budget_short;
      j["adaptive"] = {{"threshold", settings.adaptive.threshold},
                       {"depth_ratio", settings.adaptive.depth_ratio},
                       {"budget", settings.adaptive.budget},
                       {"points_refined", stats([](const frame_stats& f) { return f.refined; })},
                       {"budget_short_frames", short_frames}};
    }
    if (settings.reuse.mode != fov::reuse_mode::none)
      j["reuse"] = {{"mode", fov::label_of(fov::reuse_mode_labels, settings.reuse.mode)},
                    {"fovea_deg", settings.reuse.fovea_deg},
                    {"threshold", settings.reuse.threshold},
                    {"max_age", settings.reuse.max_age},
                    {"budget", settings.reuse.budget},
                    {"view_deg", settings.reuse.view_deg},
                    {"edges", fov::label_of(fov::reuse_edges_labels, settings.reuse.edges)},
                    {"distance", fov::label_of(fov::reuse_distance_labels, settings.reuse.distance)},
                    {"reused_share", stats([](const frame_stats& f) { return f.reused_share; })}};
    std::cout << j.dump(2) << "\n";
  }
  if (!o.gaze_log.empty()) fov::write_file_atomic(o.gaze_log, gaze_log.data(), gaze_log.size());
  if (gaze->clamped || gaze->malformed || conditioner.dropouts)
    std::cerr << fmt::format("fovview: gaze: {} samples clamped to the screen, {} malformed, {} dropouts\n", gaze->clamped,
                             gaze->malformed, conditioner.dropouts);
  return 0;
}

}  // namespace fov
