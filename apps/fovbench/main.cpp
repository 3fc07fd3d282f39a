// fovbench: sweeps point-set scale, method, k, rays per sample and gaze over scenes, and
// measures the speed/accuracy trade against full-resolution references, side by side.
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "../common/cli.h"
#include "../common/image_io.h"
#include "fov/cl_reconstruct.h"
#include "fov/knn_table.h"
#include "fov/metrics.h"
#include "fov/pointset_io.h"
#include "fov/random.h"
#include "fov/rbf_cache.h"
#include "fov/scene.h"
#include "fov/taa.h"
#include "plot.h"
#include "report.h"
#include "sweep.h"

namespace {

using json = nlohmann::json;
using fov::usage_error;
namespace fs = std::filesystem;
using clock_type = std::chrono::steady_clock;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

double ms_since(clock_type::time_point t) { return std::chrono::duration<double, std::milli>(clock_type::now() - t).count(); }

struct timing {  // median and spread of repeated measurements
  double median = 0, min = 0, max = 0;
};
timing summarise(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return {v[v.size() / 2], v.front(), v.back()};
}

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

struct gaze_point {
  std::string name;
  double x, y;
};

std::vector<gaze_point> parse_gazes(const std::vector<std::string>& items, const fov::display_geometry& d, uint64_t seed) {
  std::vector<gaze_point> out;
  for (const std::string& g : items) {
    char* end = nullptr;
    const long n = std::strtol(g.c_str(), &end, 10);
    if (!g.empty() && *end == '\0') {  // N random gazes, seeded
      if (n < 1 || n > 100) throw usage_error(fmt::format("--gazes: {} random gazes is outside 1..100", n));
      fov::rng r(fov::stream_seed(seed, 0x6a7e));
      for (long i = 0; i < n; ++i) {
        const double x = std::round(r.uniform() * d.width), y = std::round(r.uniform() * d.height);
        out.push_back({fmt::format("random{}", i + 1), x, y});
      }
      continue;
    }
    double xy[2];
    fov::require_gaze("--gazes", g, d, xy);
    out.push_back({g.find(',') == std::string::npos ? g : fmt::format("{:g}_{:g}", xy[0], xy[1]), xy[0], xy[1]});
  }
  return out;
}

// A full-resolution reference of one scene at one spp: the frame and its timing.
struct reference_frame {
  fov::frame image;
  timing ms;
  uint64_t rays = 0;
};

}  // namespace

int main(int argc, char** argv) {
  mallopt(M_MMAP_THRESHOLD, 1 << 30);  // big per-frame buffers stay in the heap (docs/fovview.md)
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  CLI::App app{"fovbench: the speed/accuracy trade of foveated ray tracing, measured"};
  fov::bench_options o;
  std::vector<std::string> method_names{"shepard"};
  std::string footprint_name = "disc";
  app.add_option("--scene", o.scenes, "Scene (repeat): builtin, a glTF/OBJ file, env:IMAGE")->take_all();
  app.add_option("--display", o.display, "fove, vive, desktop1080, or WxH (v = 1)");
  app.add_option("--scales", o.scales, "Point-set scales, e.g. 1.0,1.5,2.0")->delimiter(',');
  app.add_option("--methods", method_names, "nn,shepard,rbf")->delimiter(',');
  app.add_option("--k", o.ks, "Neighbours, e.g. 5,10,20 (nn always uses 1)")->delimiter(',');
  app.add_option("--spp", o.spps, "Rays per point and per reference pixel, e.g. 1,4,16,32")->delimiter(',');
  app.add_option("--gazes", o.gazes, "centre, corner, X,Y, or N (N seeded random gazes)")->delimiter(';');
  app.add_option("-o,--out", o.out, "Output directory (results.csv, plots, report.md, references/)");
  app.add_option("--points-dir", o.points_dir, "Where point sets are read, or generated when missing");
  app.add_option("--texture-footprint", footprint_name,
                 "Foveated rays filter textures over their share of the point's disc (disc) or of a pixel (pixel)");
  app.add_option("--frames", o.frames, "Timed frames per configuration and reference (median reported)");
  app.add_option("--temporal-frames", o.temporal_frames, "Frames of the camera path for flicker (0: skip)");
  app.add_flag("--resume", o.resume, "Skip configurations already in results.csv");
  app.add_option("--budget-psnr", o.budget_psnr, "Report the fastest configuration with PSNR >= this (dB)");
  app.add_option("--budget-foveated", o.budget_foveated, "... or with foveated error <= this");
  app.add_option("--device", o.device, "opencl or cpp");
  app.add_option("--hfov", o.hfov, "Camera field of view (default: the scene's, else 90)");
  app.add_option("--seed", o.seed, "Seed of random gazes and ray positions");

  return fov::run_tool("fovbench", app, argc, argv, [&]() -> int {
    // Gazes may contain commas (X,Y): --gazes takes ';' between items, and a plain list
    // of names with commas is split here when it holds no X,Y pair.
    std::vector<std::string> gazes;
    for (const std::string& g : o.gazes) {
      std::stringstream in(g);
      std::string part;
      std::vector<std::string> parts;
      while (std::getline(in, part, ',')) parts.push_back(part);
      bool pair = parts.size() == 2;
      for (const std::string& p : parts) pair = pair && !p.empty() && (std::isdigit(static_cast<unsigned char>(p[0])) || p[0] == '.');
      if (pair) gazes.push_back(g);
      else gazes.insert(gazes.end(), parts.begin(), parts.end());
    }
    o.gazes = gazes;
    if (o.scenes.empty()) o.scenes = {"builtin"};
    for (const std::string& m : method_names) {
      fov::method how;
      if (!fov::parse_method(m, how)) throw usage_error(fmt::format("--methods: unknown '{}' (nn, shepard, rbf)", m));
      o.methods.push_back(how);
    }
    for (double s : o.scales)
      if (!(s >= 0.5 && s <= 10)) throw usage_error(fmt::format("--scales: {} is outside 0.5..10", s));
    for (uint32_t k : o.ks)
      if (k < 1 || k > 32) throw usage_error(fmt::format("--k: {} is outside 1..32", k));
    for (uint32_t s : o.spps)
      if (s < 1 || s > 1024) throw usage_error(fmt::format("--spp: {} is outside 1..1024", s));
    if (o.frames < 1 || o.frames > 100) throw usage_error("--frames must lie in 1..100");
    if (o.temporal_frames == 1 || o.temporal_frames > 200) throw usage_error("--temporal-frames must be 0 or 2..200");
    if (o.device != "opencl" && o.device != "cpp") throw usage_error("--device: opencl or cpp");
    if (!fov::parse_texture_footprint(footprint_name, o.footprint))
      throw usage_error(fmt::format("--texture-footprint: unknown '{}' (disc, pixel)", footprint_name));
    const std::string footprint = fov::texture_footprint_name(o.footprint);
    if (!std::isnan(o.budget_psnr) && !std::isnan(o.budget_foveated)) throw usage_error("give one budget");
    fov::display_geometry display;
    if (!fov::display_preset(o.display, display)) {
      int w = 0, h = 0;
      char x = 0, extra = 0;
      std::stringstream in(o.display);
      if (!(in >> w >> x >> h) || x != 'x' || (in >> extra) || w < 8 || h < 8 || w > 8192 || h > 8192)
        throw usage_error(fmt::format("--display: '{}' is not fove, vive, desktop1080 or WxH (8..8192)", o.display));
      display = {w, h, 1.0};
    }
    const std::vector<gaze_point> gaze_points = parse_gazes(o.gazes, display, o.seed);
    for (const std::string& scene : o.scenes) {  // fail before any output, not an hour in
      const std::string file = scene.rfind("env:", 0) == 0 ? scene.substr(4) : scene;
      if (scene != "builtin" && !fs::is_regular_file(file))
        throw std::runtime_error(fmt::format("--scene {}: no such file", scene));
    }
    fs::create_directories(fs::path(o.out) / "references");
    const std::string results_path = (fs::path(o.out) / "results.csv").string();
    std::set<std::string> done;
    if (fs::exists(results_path)) {
      if (!o.resume) throw std::runtime_error(fmt::format("{} exists: add --resume to continue that sweep, or choose another -o", results_path));
      for (const fov::result_row& r : fov::read_results(results_path)) {
        if (r.text("texture_footprint") != footprint)  // one footprint per results.csv: it is not in the key
          throw std::runtime_error(fmt::format("{}: its rows were traced with --texture-footprint {}, not {}; use another -o",
                                               results_path, r.text("texture_footprint"), footprint));
        done.insert(r.key());
      }
    }
    fov::results_writer writer(results_path);

    // Every configuration, in loop order; the ones to measure are those not done.
    struct config {
      size_t scene, scale, gaze;
      fov::method how;
      uint32_t k, spp;
      std::string key;
    };
    std::vector<config> all;
    for (size_t sc = 0; sc < o.scenes.size(); ++sc)
      for (size_t si = 0; si < o.scales.size(); ++si)
        for (size_t g = 0; g < gaze_points.size(); ++g)
          for (uint32_t spp : o.spps)
            for (fov::method how : o.methods)
              for (uint32_t k : how == fov::method::nn ? std::vector<uint32_t>{1} : o.ks) {
                fov::result_row r;
                r.cells = {{"scene", o.scenes[sc]}, {"gaze", gaze_points[g].name}, {"scale", fmt::format("{:.2f}", o.scales[si])},
                           {"method", fov::method_name(how)}, {"k", std::to_string(k)}, {"spp", std::to_string(spp)}};
                const std::string key = r.key();
                if (std::none_of(all.begin(), all.end(), [&](const config& c) { return c.key == key; }))
                  all.push_back({sc, si, g, how, k, spp, key});
              }
    size_t todo = 0;
    for (const config& c : all) todo += !done.count(c.key);
    std::cerr << fmt::format("fovbench: {} configurations, {} already in {}, {} to measure\n", all.size(), all.size() - todo,
                             results_path, todo);
    const uint32_t best_spp = *std::max_element(o.spps.begin(), o.spps.end());
    const auto sweep_start = clock_type::now();
    size_t measured = 0;
    auto progress = [&](const std::string& what) {
      const double elapsed = ms_since(sweep_start) / 1000;
      const double eta = measured ? elapsed / double(measured) * double(todo - measured) : 0;
      const int bar = todo ? int(30 * measured / todo) : 30;
      std::cerr << fmt::format("\r[{}{}] {}/{} {:<44.44} elapsed {:.0f}s, ETA {}", std::string(size_t(bar), '#'),
                               std::string(size_t(30 - bar), '.'), measured, todo, what, elapsed,
                               measured ? fmt::format("{:.0f}s", eta) : std::string("?"))
                << std::flush;
    };

    for (size_t sc = 0; sc < o.scenes.size() && measured < todo; ++sc) {
      bool scene_needed = false;
      for (const config& c : all) scene_needed |= c.scene == sc && !done.count(c.key);
      if (!scene_needed) continue;
      progress("loading " + o.scenes[sc]);
      std::shared_ptr<const fov::scene> scn = fov::load_scene(o.scenes[sc]);
      for (const std::string& w : scn->warnings()) std::cerr << "\nfovbench: warning: " << w << "\n";
      fov::camera cam = scn->default_camera(o.hfov > 0 ? float(o.hfov) : 90.0f);
      if (o.hfov > 0) cam.hfov_deg = float(o.hfov);
      {  // untimed: textures are read and MIP-mapped on first use (docs/reconstruction.md)
        fov::trace_params once;
        once.spp = 1;
        fov::trace_reference(*scn, cam, display.width, display.height, once);
      }
      // References per spp, cached on disk: the image (EXR) and its timing (JSON).
      std::map<uint32_t, reference_frame> refs;
      auto reference = [&](uint32_t spp) -> const reference_frame& {
        auto it = refs.find(spp);
        if (it != refs.end()) return it->second;
        const std::string base = (fs::path(o.out) / "references" / fmt::format("{}-{}x{}-spp{}", slug(o.scenes[sc]),
                                                                                display.width, display.height, spp)).string();
        reference_frame r;
        if (fs::exists(base + ".exr") && fs::exists(base + ".json")) {
          r.image = fov::read_frame(base + ".exr");
          std::ifstream in(base + ".json");
          const json j = json::parse(in);
          r.ms = {j.at("ms").get<double>(), j.at("ms_min").get<double>(), j.at("ms_max").get<double>()};
          r.rays = j.at("rays").get<uint64_t>();
        } else {
          progress(fmt::format("reference {} spp", spp));
          fov::trace_params tp;
          tp.spp = spp;
          tp.seed = o.seed;
          std::vector<double> ms;
          for (uint32_t f = 0; f < o.frames; ++f) {
            const auto t0 = clock_type::now();
            r.image = fov::trace_reference(*scn, cam, display.width, display.height, tp);
            ms.push_back(ms_since(t0));
          }
          r.ms = summarise(ms);
          r.rays = r.image.rays;
          fov::write_frame(r.image, base + ".exr");
          const std::string text = json{{"scene", o.scenes[sc]}, {"spp", spp}, {"ms", r.ms.median}, {"ms_min", r.ms.min},
                                        {"ms_max", r.ms.max}, {"rays", r.rays}, {"frames", o.frames}}.dump(2) + "\n";
          fov::write_file_atomic(base + ".json", text.data(), text.size());
        }
        return refs.emplace(spp, std::move(r)).first->second;
      };

      for (size_t si = 0; si < o.scales.size(); ++si) {
        bool scale_needed = false;
        for (const config& c : all) scale_needed |= c.scene == sc && c.scale == si && !done.count(c.key);
        if (!scale_needed) continue;
        const std::string set_path = (fs::path(o.points_dir) / fmt::format("{}-s{:.2f}.fovset",
            fov::display_preset(o.display, display) ? o.display : fmt::format("{}x{}", display.width, display.height), o.scales[si])).string();
        if (!fs::exists(set_path)) {
          progress(fmt::format("generating {}", set_path));
          fov::spacing_model model;
          model.display = display;
          model.scale = o.scales[si];
          fs::create_directories(o.points_dir);
          fov::save_pointset(set_path, fov::generate_pointset(model, {}, {}));
        }
        const fov::pointset set = fov::load_pointset(set_path);
        if (set.model.display.width != display.width || set.model.display.height != display.height)
          throw std::runtime_error(fmt::format("{}: made for {}x{}, not {}x{}", set_path, set.model.display.width,
                                               set.model.display.height, display.width, display.height));
        for (uint32_t k : o.ks)
          if (k > set.table.k) throw usage_error(fmt::format("--k {} exceeds the k = {} of {}", k, set.table.k, set_path));
        std::unique_ptr<fov::cl_reconstructor> device;
        if (o.device == "opencl") {
          device = std::make_unique<fov::cl_reconstructor>(set);
          if (!device->available()) std::cerr << "\nfovbench: warning: " << device->reason() << "; using the C++ path\n";
        }
        std::map<uint32_t, std::unique_ptr<fov::rbf_weight_cache>> cpu_caches;
        auto rebuild = [&](const fov::point_samples& s, const fov::reconstruct_params& rp) {
          if (device) return device->run(s, rp);
          if (rp.how != fov::method::rbf) return fov::reconstruct(set, s, rp);
          auto& cache = cpu_caches[rp.k];
          if (!cache) cache = std::make_unique<fov::rbf_weight_cache>(set, rp);
          return fov::reconstruct(set, s, rp, nullptr, cache.get());
        };
        const std::string device_name = device && device->available() ? device->device() : "C++ (TBB)";

        for (size_t g = 0; g < gaze_points.size(); ++g)
          for (uint32_t spp : o.spps) {
            std::vector<const config*> here;
            for (const config& c : all)
              if (c.scene == sc && c.scale == si && c.gaze == g && c.spp == spp && !done.count(c.key)) here.push_back(&c);
            if (here.empty()) continue;
            const gaze_point& gp = gaze_points[g];
            const reference_frame& ref = reference(spp);
            const reference_frame& best = reference(best_spp);
            // Trace timing per k read (the traced points depend on it), and one trace at
            // the largest k whose colours serve every method (a point's rays do not depend on k).
            fov::trace_params tp;
            tp.spp = spp;
            tp.seed = o.seed;
            tp.footprint = o.footprint;
            std::map<uint32_t, timing> trace_ms;
            std::map<uint32_t, uint64_t> trace_rays, trace_points;
            fov::point_samples samples;
            uint32_t widest = 0;
            for (const config* c : here) widest = std::max(widest, c->k);
            for (const config* c : here) {
              if (trace_ms.count(c->k)) continue;
              progress(fmt::format("tracing {} s={:.2f} {} spp={} k={}", slug(o.scenes[sc]), o.scales[si], gp.name, spp, c->k));
              std::vector<double> ms;
              for (uint32_t f = 0; f < o.frames; ++f) {
                const auto t0 = clock_type::now();
                fov::point_samples s = fov::trace_points(*scn, cam, set, gp.x, gp.y, c->k, tp);
                ms.push_back(ms_since(t0));
                trace_rays[c->k] = s.rays, trace_points[c->k] = s.traced.size();
                if (c->k == widest) samples = std::move(s);
              }
              trace_ms[c->k] = summarise(ms);
            }
            for (const config* c : here) {
              progress(fmt::format("{} s={:.2f} {} {} k={} spp={}", slug(o.scenes[sc]), o.scales[si], gp.name,
                                   fov::method_name(c->how), c->k, spp));
              fov::reconstruct_params rp;
              rp.how = c->how;
              rp.k = c->k;
              rebuild(samples, rp);  // untimed: kernel compilation, RBF weights
              std::vector<double> ms;
              fov::frame image;
              for (uint32_t f = 0; f < o.frames; ++f) {
                const auto t0 = clock_type::now();
                image = rebuild(samples, rp);
                ms.push_back(ms_since(t0));
              }
              const timing rec = summarise(ms), tr = trace_ms[c->k];
              const timing frame{tr.median + rec.median, tr.min + rec.min, tr.max + rec.max};
              const fov::spacing_model eye{display, 1.0, set.model.acuity};
              const fov::error_report e = fov::measure_error(image, ref.image, eye, gp.x, gp.y);
              const fov::error_report vs_best = fov::measure_error(image, best.image, eye, gp.x, gp.y);
              std::string profile;
              for (double v : e.profile_rmse) profile += (profile.empty() ? "" : ";") + fmt::format("{:.5f}", v);
              fov::result_row row;
              row.cells = {{"scene", o.scenes[sc]}, {"gaze", gp.name}, {"gaze_x", number(gp.x)}, {"gaze_y", number(gp.y)},
                           {"scale", fmt::format("{:.2f}", o.scales[si])}, {"method", fov::method_name(c->how)},
                           {"k", std::to_string(c->k)}, {"spp", std::to_string(spp)},
                           {"texture_footprint", footprint},
                           {"points_traced", std::to_string(trace_points[c->k])}, {"rays", std::to_string(trace_rays[c->k])},
                           {"reference_rays", std::to_string(ref.rays)}, {"trace_ms", number(tr.median)},
                           {"reconstruct_ms", number(rec.median)}, {"frame_ms", number(frame.median)},
                           {"frame_ms_min", number(frame.min)}, {"frame_ms_max", number(frame.max)},
                           {"reference_ms", number(ref.ms.median)}, {"reference_ms_min", number(ref.ms.min)},
                           {"reference_ms_max", number(ref.ms.max)}, {"speedup", number(ref.ms.median / frame.median)},
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
                           {"device", device_name}, {"frames", std::to_string(o.frames)}};
              // Temporal quality: the camera turns 0.15 degrees a frame while the gaze
              // drifts 3 px a frame; flicker is the mean frame-to-frame luminance change.
              if (o.temporal_frames >= 2) {
                progress(fmt::format("temporal {} {} k={} spp={}", slug(o.scenes[sc]), fov::method_name(c->how), c->k, spp));
                fov::taa_state taa;
                fov::frame previous_raw, previous_taa, previous_ref;
                double raw = 0, blended = 0, reference_flicker = 0;
                for (uint32_t f = 0; f < o.temporal_frames; ++f) {
                  const float yaw = glm::radians(0.15f * float(f));
                  fov::camera moved = cam;
                  const glm::vec3 right = glm::normalize(glm::cross(cam.forward, cam.up));
                  moved.forward = glm::normalize(cam.forward * std::cos(yaw) + right * std::sin(yaw));
                  const double gx = std::clamp(gp.x + 3.0 * f, 0.0, double(display.width)), gy = gp.y;
                  const fov::point_samples s = fov::trace_points(*scn, moved, set, gx, gy, c->k, tp);
                  const fov::frame now = rebuild(s, rp);
                  const double gaze[2] = {gx, gy};
                  const fov::frame now_taa = device ? device->run_taa(s, rp, taa, moved, gaze)
                                                    : fov::taa_resolve(taa, now, moved, display, gaze);
                  fov::trace_params rtp = tp;
                  const fov::frame now_ref = fov::trace_reference(*scn, moved, display.width, display.height, rtp);
                  if (f > 0) {
                    raw += fov::mean_luminance_change(now, previous_raw);
                    blended += fov::mean_luminance_change(now_taa, previous_taa);
                    reference_flicker += fov::mean_luminance_change(now_ref, previous_ref);
                  }
                  previous_raw = now, previous_taa = now_taa, previous_ref = now_ref;
                }
                const double pairs = double(o.temporal_frames - 1);
                row.cells["flicker"] = number(raw / pairs);
                row.cells["flicker_taa"] = number(blended / pairs);
                row.cells["flicker_reference"] = number(reference_flicker / pairs);
              }
              writer.append(row);
              done.insert(c->key);
              ++measured;
            }
          }
      }
    }
    progress("done");
    std::cerr << "\n";

    // Figures and the report from every row, this run's and earlier ones.
    const std::vector<fov::result_row> rows = fov::read_results(results_path);
    fov::write_bench_figures(rows, o, fs::path(o.out).string());
    fov::write_bench_report(rows, o, (fs::path(o.out) / "report.md").string(), argc, argv);
    std::cout << fmt::format("{} rows in {}; figures and report.md in {}\n", rows.size(), results_path, o.out);
    return 0;
  });
}
