#include "bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "../common/cli.h"
#include "../common/image_io.h"
#include "fov/flicker.h"
#include "fov/metrics.h"
#include "fov/pointset_io.h"
#include "fov/random.h"

namespace fov {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

std::string number(double v) {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.6g}", v);
}

std::string slug(const std::string& scene) {
  std::string s = fs::path(scene.substr(scene.rfind(':') == std::string::npos ? 0 : scene.rfind(':') + 1)).stem().string();
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '-';
  return (scene.rfind("env:", 0) == 0 ? "env-" : "") + s;
}

// One configuration of the sweep.
struct config {
  size_t scene, scale, gaze;
  method how;
  uint32_t k, spp;
  std::string key;
};

std::vector<config> all_configs(const bench_options& o, const std::vector<named_gaze>& gazes) {
  std::vector<config> all;
  for (size_t sc = 0; sc < o.scenes.size(); ++sc)
    for (size_t si = 0; si < o.scales.size(); ++si)
      for (size_t g = 0; g < gazes.size(); ++g)
        for (uint32_t spp : o.spps)
          for (method how : o.methods)
            for (uint32_t k : how == method::nn ? std::vector<uint32_t>{1} : o.ks) {
              result_row r;
              r.cells = {{"scene", o.scenes[sc]}, {"gaze", gazes[g].name}, {"scale", fmt::format("{:.2f}", o.scales[si])},
                         {"method", method_name(how)}, {"k", std::to_string(k)}, {"spp", std::to_string(spp)}};
              const std::string key = r.key();
              if (std::none_of(all.begin(), all.end(), [&](const config& c) { return c.key == key; }))
                all.push_back({sc, si, g, how, k, spp, key});
            }
  return all;
}

// The set for one scale, generated when missing.
std::shared_ptr<const pointset> bench_pointset(const bench_options& o, const display_geometry& display, double scale,
                                               const std::function<void(const std::string&)>& say) {
  display_geometry preset;
  const std::string name = display_preset(o.display, preset) ? o.display : fmt::format("{}x{}", display.width, display.height);
  const std::string path = (fs::path(o.points_dir) / fmt::format("{}-s{:.2f}.fovset", name, scale)).string();
  if (!fs::exists(path)) {
    say(fmt::format("generating {}", path));
    spacing_model model;
    model.display = display;
    model.scale = scale;
    fs::create_directories(o.points_dir);
    save_pointset(path, generate_pointset(model, {}, {}));
  }
  auto set = std::make_shared<const pointset>(load_pointset(path));
  if (set->model.display.width != display.width || set->model.display.height != display.height)
    throw std::runtime_error(fmt::format("{}: made for {}x{}, not {}x{}", path, set->model.display.width,
                                         set->model.display.height, display.width, display.height));
  for (uint32_t k : o.ks)
    if (k > set->table.k) throw usage_error(fmt::format("--k {} exceeds the k = {} of {}", k, set->table.k, path));
  return set;
}

}  // namespace

timing summarise(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return {v[v.size() / 2], v.front(), v.back()};
}

reference_cache::reference_cache(std::string dir, std::string scene, const display_geometry& d, uint32_t frames)
    : dir_(std::move(dir)), scene_(std::move(scene)), display_(d), frames_(frames) {}

std::string reference_cache::file_base(uint32_t spp) const {
  return (fs::path(dir_) / fmt::format("{}-{}x{}-spp{}", slug(scene_), display_.width, display_.height, spp)).string();
}

const reference_frame& reference_cache::get(renderer& r, const render_params& base, uint32_t spp,
                                            const std::function<void(const std::string&)>& say) {
  auto it = refs_.find(spp);
  if (it != refs_.end()) return it->second;
  const std::string file = file_base(spp);
  reference_frame ref;
  if (fs::exists(file + ".exr") && fs::exists(file + ".json")) {
    ref.image = read_frame(file + ".exr");
    std::ifstream in(file + ".json");
    const json j = json::parse(in);
    ref.ms = {j.at("ms").get<double>(), j.at("ms_min").get<double>(), j.at("ms_max").get<double>()};
    ref.rays = j.at("rays").get<uint64_t>();
    ref.from_disk = true;
  } else {
    if (say) say(fmt::format("reference {} spp", spp));
    render_params p = base;
    p.spp = spp;
    std::vector<double> ms;
    for (uint32_t f = 0; f < frames_; ++f) {
      frame_timing t;
      ref.image = r.reference(display_.width, display_.height, p, &t).image;
      ms.push_back(t.trace_ms);
    }
    ref.ms = summarise(ms);
    ref.rays = ref.image.rays;
    write_frame(ref.image, file + ".exr");
    const std::string text = json{{"scene", scene_}, {"spp", spp}, {"ms", ref.ms.median}, {"ms_min", ref.ms.min},
                                  {"ms_max", ref.ms.max}, {"rays", ref.rays}, {"frames", frames_}}.dump(2) + "\n";
    write_file_atomic(file + ".json", text.data(), text.size());
  }
  return refs_.emplace(spp, std::move(ref)).first->second;
}

std::vector<named_gaze> parse_gazes(const std::vector<std::string>& items, const display_geometry& d, uint64_t seed) {
  std::vector<named_gaze> out;
  for (const std::string& g : items) {
    char* end = nullptr;
    const long n = std::strtol(g.c_str(), &end, 10);
    if (!g.empty() && *end == '\0') {  // N random gazes, seeded
      if (n < 1 || n > 100) throw usage_error(fmt::format("--gazes: {} random gazes is outside 1..100", n));
      rng r(stream_seed(seed, 0x6a7e));
      for (long i = 0; i < n; ++i) {
        const double x = std::round(r.uniform() * d.width), y = std::round(r.uniform() * d.height);
        out.push_back({fmt::format("random{}", i + 1), {x, y}});
      }
      continue;
    }
    const gaze_point at = require_gaze("--gazes", g, d);
    out.push_back({g.find(',') == std::string::npos ? g : fmt::format("{:g}_{:g}", at.x, at.y), at});
  }
  return out;
}

display_geometry parse_display(const std::string& text) {
  display_geometry display;
  if (display_preset(text, display)) return display;
  int w = 0, h = 0;
  char x = 0, extra = 0;
  std::stringstream in(text);
  if (!(in >> w >> x >> h) || x != 'x' || (in >> extra) || w < 8 || h < 8 || w > 8192 || h > 8192)
    throw usage_error(fmt::format("--display: '{}' is not fove, vive, desktop1080 or WxH (8..8192)", text));
  return {w, h, 1.0};
}

std::string render_settings_label(const render_params& p) {
  auto point = [](const std::optional<glm::vec3>& v) {
    return v ? fmt::format("{:g},{:g},{:g}", v->x, v->y, v->z) : std::string("-");  // -: the scene camera's
  };
  return fmt::format("seed={} shadows={} renka={} rbf_kernel={} rbf_shape={:g} hfov={:g} eye={} look_at={} up={}", p.seed,
                     p.shadows ? 1 : 0, p.reconstruct.renka ? 1 : 0, label_of(rbf_kernel_labels, p.reconstruct.kernel),
                     p.reconstruct.shape, p.view.hfov_deg, point(p.view.eye), point(p.view.target), point(p.view.up));
}

display_geometry check_bench_options(const bench_options& o) {
  for (double s : o.scales)
    if (!(s >= 0.5 && s <= 10)) throw usage_error(fmt::format("--scales: {} is outside 0.5..10", s));
  for (uint32_t k : o.ks)
    if (k < 1 || k > max_knn) throw usage_error(fmt::format("--k: {} is outside 1..{}", k, max_knn));
  for (uint32_t s : o.spps)
    if (s < 1 || s > max_spp) throw usage_error(fmt::format("--spp: {} is outside 1..{}", s, max_spp));
  if (o.spps.empty() || o.ks.empty() || o.methods.empty() || o.scales.empty() || o.gazes.empty())
    throw usage_error("--scales, --methods, --k, --spp and --gazes each need at least one value");
  if (o.frames < 1 || o.frames > 100) throw usage_error("--frames must lie in 1..100");
  if (o.temporal_frames == 1 || o.temporal_frames > 200) throw usage_error("--temporal-frames must be 0 or 2..200");
  if (!std::isnan(o.budget_psnr) && !std::isnan(o.budget_foveated)) throw usage_error("give one budget");
  const std::string problem = validate(o.render);
  if (!problem.empty()) throw usage_error(problem);
  const display_geometry display = parse_display(o.display);
  parse_gazes(o.gazes, display, o.render.seed);
  for (const std::string& scene : o.scenes) {  // fail before any output, not an hour in
    const std::string file = scene.rfind("env:", 0) == 0 ? scene.substr(4) : scene;
    if (scene != "builtin" && !fs::is_regular_file(file))
      throw std::runtime_error(fmt::format("--scene {}: no such file", scene));
  }
  return display;
}

size_t run_bench(const bench_options& o, const bench_reporter& report) {
  const display_geometry display = check_bench_options(o);
  const std::vector<named_gaze> gazes = parse_gazes(o.gazes, display, o.render.seed);
  const std::string footprint = texture_footprint_name(o.render.footprint);
  const std::string settings = render_settings_label(o.render);
  const std::string results_path = (fs::path(o.out) / "results.csv").string();
  std::set<std::string> done;
  if (fs::exists(results_path)) {
    if (!o.resume)
      throw std::runtime_error(fmt::format("{} exists: add --resume to continue that sweep, or choose another -o", results_path));
    for (const result_row& r : read_results(results_path)) {
      // One footprint and one setting per results.csv: they are not in the key.
      if (r.text("texture_footprint") != footprint)
        throw std::runtime_error(fmt::format("{}: its rows were traced with --texture-footprint {}, not {}; use another -o",
                                             results_path, r.text("texture_footprint"), footprint));
      if (r.text("render_settings") != settings)
        throw std::runtime_error(fmt::format("{}: its rows were measured with {}, not {}; use another -o", results_path,
                                             r.text("render_settings"), settings));
      done.insert(r.key());
    }
  }
  const std::vector<config> all = all_configs(o, gazes);
  size_t todo = 0;
  for (const config& c : all) todo += !done.count(c.key);
  const uint32_t best_spp = *std::max_element(o.spps.begin(), o.spps.end());
  size_t measured = 0;
  const std::function<void(const std::string&)> say = [&](const std::string& what) { report.progress(measured, todo, what); };
  auto needed = [&](auto&& match) {
    return std::any_of(all.begin(), all.end(), [&](const config& c) { return match(c) && !done.count(c.key); });
  };

  // Every scene the sweep needs is loaded, and its camera set up, before anything is
  // measured: a broken scene listed last fails now, not after an hour of the others.
  std::vector<std::shared_ptr<const scene>> scenes(o.scenes.size());
  for (size_t sc = 0; sc < o.scenes.size(); ++sc) {
    if (!needed([&](const config& c) { return c.scene == sc; })) continue;
    say("loading " + o.scenes[sc]);
    scenes[sc] = load_scene(o.scenes[sc]);
    for (const std::string& w : scenes[sc]->warnings()) report.line("warning: " + w);
    setup_camera(*scenes[sc], o.render.view);
  }
  // Only now is anything written.
  report.line(fmt::format("{} configurations, {} already in {}, {} to measure", all.size(), all.size() - todo, results_path, todo));
  fs::create_directories(fs::path(o.out) / "references");
  results_writer writer(results_path);
  for (size_t sc = 0; sc < o.scenes.size() && measured < todo; ++sc) {
    if (!scenes[sc]) continue;
    std::shared_ptr<const scene> scn = std::move(scenes[sc]);
    renderer r(scn, o.render);
    r.warm_up_reference(display.width, display.height, o.render);  // textures read and MIP-mapped on first use
    reference_cache references((fs::path(o.out) / "references").string(), o.scenes[sc], display, o.frames);
    auto reference = [&](uint32_t spp) -> const reference_frame& {
      return references.get(r, o.render, spp, say);
    };
    for (size_t si = 0; si < o.scales.size(); ++si) {
      if (!needed([&](const config& c) { return c.scene == sc && c.scale == si; })) continue;
      r.use_pointset(bench_pointset(o, display, o.scales[si], say));
      if (const std::string warning = r.device_warning(); !warning.empty()) report.line(warning);
      const pointset& set = *r.current_set();
      for (size_t g = 0; g < gazes.size(); ++g)
        for (uint32_t spp : o.spps) {
          std::vector<const config*> here;
          for (const config& c : all)
            if (c.scene == sc && c.scale == si && c.gaze == g && c.spp == spp && !done.count(c.key)) here.push_back(&c);
          if (here.empty()) continue;
          const named_gaze& gp = gazes[g];
          const reference_frame& ref = reference(spp);
          const reference_frame& best = reference(best_spp);
          render_params p = o.render;
          p.spp = spp;
          // Trace timing per k read (the traced points depend on it), and one trace at the
          // largest k whose colours serve every method (a point's rays do not depend on k).
          std::map<uint32_t, timing> trace_ms;
          std::map<uint32_t, uint64_t> trace_rays, trace_points;
          point_samples samples;
          uint32_t widest = 0;
          for (const config* c : here) widest = std::max(widest, c->k);
          for (const config* c : here) {
            if (trace_ms.count(c->k)) continue;
            say(fmt::format("tracing {} s={:.2f} {} spp={} k={}", slug(o.scenes[sc]), o.scales[si], gp.name, spp, c->k));
            p.reconstruct.k = c->k;
            std::vector<double> ms;
            for (uint32_t f = 0; f < o.frames; ++f) {
              frame_timing t;
              points_trace traced = r.trace(gp.at, p, t);
              ms.push_back(t.trace_ms);
              trace_rays[c->k] = t.rays, trace_points[c->k] = t.points_traced;
              if (c->k == widest) samples = std::move(traced.samples);
            }
            trace_ms[c->k] = summarise(ms);
          }
          for (const config* c : here) {
            say(fmt::format("{} s={:.2f} {} {} k={} spp={}", slug(o.scenes[sc]), o.scales[si], gp.name, method_name(c->how),
                            c->k, spp));
            p.reconstruct.how = c->how;
            p.reconstruct.k = c->k;
            r.prepare(samples, p);  // untimed: kernel compilation, RBF weights
            std::vector<double> ms;
            frame_timing t;
            for (uint32_t f = 0; f < o.frames; ++f) {
              r.reconstruct(samples, gp.at, p, t);
              ms.push_back(t.reconstruct_ms);
            }
            const frame image = r.reconstruct(samples, gp.at, p, t);
            const timing rec = summarise(ms), tr = trace_ms[c->k];
            const timing frame_ms{tr.median + rec.median, tr.min + rec.min, tr.max + rec.max};
            const spacing_model eye{display, 1.0, set.model.acuity};
            const error_report e = measure_error(image, ref.image, eye, gp.at);
            const error_report vs_best = measure_error(image, best.image, eye, gp.at);
            std::string profile;
            for (double v : e.profile_rmse) profile += (profile.empty() ? "" : ";") + fmt::format("{:.5f}", v);
            result_row row;
            row.cells = {{"scene", o.scenes[sc]}, {"gaze", gp.name}, {"gaze_x", number(gp.at.x)}, {"gaze_y", number(gp.at.y)},
                         {"scale", fmt::format("{:.2f}", o.scales[si])}, {"method", method_name(c->how)},
                         {"k", std::to_string(c->k)}, {"spp", std::to_string(spp)}, {"texture_footprint", footprint},
                         {"points_traced", std::to_string(trace_points[c->k])}, {"rays", std::to_string(trace_rays[c->k])},
                         {"reference_rays", std::to_string(ref.rays)}, {"trace_ms", number(tr.median)},
                         {"reconstruct_ms", number(rec.median)}, {"frame_ms", number(frame_ms.median)},
                         {"frame_ms_min", number(frame_ms.min)}, {"frame_ms_max", number(frame_ms.max)},
                         {"reference_ms", number(ref.ms.median)}, {"reference_ms_min", number(ref.ms.min)},
                         {"reference_ms_max", number(ref.ms.max)}, {"speedup", number(ref.ms.median / frame_ms.median)},
                         {"psnr", number(e.overall.psnr)}, {"ssim", number(e.overall.ssim)},
                         {"psnr_fovea", number(e.bands[0].psnr)}, {"ssim_fovea", number(e.bands[0].ssim)},
                         {"psnr_5_10", number(e.bands[1].psnr)}, {"ssim_5_10", number(e.bands[1].ssim)},
                         {"psnr_10_20", number(e.bands[2].psnr)}, {"ssim_10_20", number(e.bands[2].ssim)},
                         {"psnr_20_30", number(e.bands[3].psnr)}, {"ssim_20_30", number(e.bands[3].ssim)},
                         {"psnr_periphery", number(e.bands[4].psnr)}, {"ssim_periphery", number(e.bands[4].ssim)},
                         {"foveated_error", number(e.foveated_error)}, {"foveated_psnr", number(e.foveated_psnr)},
                         {"psnr_vs_best_reference", number(vs_best.overall.psnr)},
                         {"foveated_error_vs_best", number(vs_best.foveated_error)},
                         {"best_reference_spp", std::to_string(best_spp)}, {"error_profile", profile},
                         {"device", r.device()}, {"frames", std::to_string(o.frames)}, {"render_settings", settings}};
            if (o.temporal_frames >= 2) {
              say(fmt::format("temporal {} {} k={} spp={}", slug(o.scenes[sc]), method_name(c->how), c->k, spp));
              flicker_params fp;
              fp.frames = o.temporal_frames;
              const flicker_report fl = measure_flicker(r, gp.at, p, fp);
              row.cells["flicker"] = number(fl.raw);
              row.cells["flicker_taa"] = number(fl.taa);
              row.cells["flicker_reference"] = number(fl.reference);
            }
            writer.append(row);
            done.insert(c->key);
            ++measured;
          }
        }
    }
  }
  say("done");
  return measured;
}

}  // namespace fov
