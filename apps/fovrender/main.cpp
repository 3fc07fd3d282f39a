// fovrender: renders one frame headless, foveated or at full resolution, and compares.
#include <chrono>
#include <filesystem>
#include <cmath>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "../common/cli.h"
#include "../common/debug_views.h"
#include "../common/image_io.h"
#include "fov/cl_reconstruct.h"
#include "fov/rbf_cache.h"
#include "fov/metrics.h"
#include "fov/taa.h"
#include "fov/pointset_io.h"
#include "fov/reconstruct.h"

namespace {

using json = nlohmann::json;
using fov::usage_error;

double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

json band_json(const fov::band_metrics& m) {
  return {{"psnr", std::isfinite(m.psnr) ? json(m.psnr) : json("inf")}, {"ssim", m.ssim}, {"pixels", m.pixels}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fovrender: render one frame foveated (or at full resolution) and measure it"};
  std::string scene_spec = "builtin", points_file, gaze_text = "centre", method_text = "shepard", compare;
  std::vector<std::string> outputs;
  uint32_t k = 5, spp = 32, taa_frames = 0;
  std::string pattern = "reseed", footprint_text = "disc";
  std::string kernel_text = "multiquadric", device_text = "opencl", debug_view, debug_output;
  double shape = 1.0;
  uint64_t seed = 1;
  int width = 1280, height = 1440;
  double hfov = 0;
  bool reference = false, renka = false, as_json = false, no_shadows = false, no_warmup = false;
  app.add_option("--scene", scene_spec, "builtin, a glTF/OBJ file, or env:IMAGE");
  app.add_option("--points", points_file, "Point set (.fovset); gives the screen size");
  app.add_option("--gaze", gaze_text, "X,Y in screen pixels, centre or corner");
  app.add_option("--method", method_text, "nn, shepard or rbf");
  app.add_option("--k", k, "Neighbours each pixel reads (1..the set's k)");
  app.add_flag("--renka", renka, "Shepard with Renka's squared weights");
  app.add_option("--rbf-kernel", kernel_text, "RBF kernel: multiquadric or gaussian");
  app.add_option("--rbf-shape", shape, "RBF shape c in units of the neighbours' mean spacing p");
  app.add_option("--spp", spp, "Rays per point (foveated) or per pixel (reference)");
  app.add_option("--seed", seed, "Seed of the ray positions");
  app.add_flag("--reference", reference, "Render at full resolution instead");
  app.add_option("--width", width, "Screen width without --points");
  app.add_option("--height", height, "Screen height without --points");
  app.add_option("--hfov", hfov, "Horizontal field of view in degrees (default: the scene's camera, else 90)");
  app.add_flag("--no-shadows", no_shadows, "Skip shadow rays");
  app.add_option("--texture-footprint", footprint_text,
                 "Foveated rays filter textures over their share of the point's disc (disc, default) or of a pixel "
                 "(pixel: sharper, cheaper, aliased periphery)");
  app.add_option("--taa-frames", taa_frames, "Render this many frames of the view with TAA");
  app.add_option("--pattern", pattern, "With --taa-frames: reseed (new ray positions each frame), mirror (the set "
                                       "mirrored: four patterns, thesis Sec. 3.3) or fixed");
  app.add_flag("--no-warmup", no_warmup, "Time the first frame, texture loading included");
  app.add_option("--device", device_text, "Reconstruct with opencl (default; falls back with a warning) or cpp");
  app.add_option("-o,--output", outputs, "Output image (.exr linear, .png sRGB); may be repeated");
  app.add_option("--debug-view", debug_view, "points, density or eccentricity: write that overlay too");
  app.add_option("--debug-output", debug_output, "File for the overlay (default: the first -o with '-VIEW' before the extension)");
  app.add_option("--compare", compare, "Reference image: print PSNR/SSIM overall and by eccentricity band");
  app.add_flag("--json", as_json, "Print JSON");
  return fov::run_tool("fovrender", app, argc, argv, [&] {
    fov::method how;
    if (!fov::parse_method(method_text, how))
      throw usage_error(fmt::format("--method: unknown '{}' (nn, shepard, rbf)", method_text));
    if (kernel_text != "multiquadric" && kernel_text != "gaussian")
      throw usage_error(fmt::format("--rbf-kernel: unknown '{}' (multiquadric, gaussian)", kernel_text));
    if (!(shape > 0) || !std::isfinite(shape)) throw usage_error(fmt::format("--rbf-shape must be positive (got {})", shape));
    if (!debug_view.empty() && debug_view != "points" && debug_view != "density" && debug_view != "eccentricity")
      throw usage_error(fmt::format("--debug-view: unknown '{}' (points, density, eccentricity)", debug_view));
    if (!debug_view.empty() && debug_output.empty() && outputs.empty())
      throw usage_error("--debug-view needs -o or --debug-output");
    if (device_text != "opencl" && device_text != "cpp")
      throw usage_error(fmt::format("--device: unknown '{}' (opencl, cpp)", device_text));
    if (spp < 1 || spp > 65535) throw usage_error(fmt::format("--spp must lie in 1..65535 (got {})", spp));
    if (hfov != 0 && !(hfov > 0 && hfov < 180)) throw usage_error(fmt::format("--hfov must lie in (0, 180) (got {})", hfov));
    if (outputs.empty() && compare.empty()) throw usage_error("nothing to do: give -o and/or --compare");
    if (!reference && points_file.empty()) throw usage_error("--points is required unless --reference");
    if (reference && taa_frames > 0) throw usage_error("--taa-frames applies to foveated frames, not --reference");
    if (taa_frames > 10000) throw usage_error(fmt::format("--taa-frames must lie in 0..10000 (got {})", taa_frames));
    fov::texture_footprint footprint;
    if (!fov::parse_texture_footprint(footprint_text, footprint))
      throw usage_error(fmt::format("--texture-footprint: unknown '{}' (disc, pixel)", footprint_text));
    if (pattern != "reseed" && pattern != "mirror" && pattern != "fixed")
      throw usage_error(fmt::format("--pattern: unknown '{}' (reseed, mirror, fixed)", pattern));

    fov::pointset set;
    fov::display_geometry display{width, height, 1.0};
    if (!points_file.empty()) {
      set = fov::load_pointset(points_file);
      display = set.model.display;
      if (k < 1 || k > set.table.k)
        throw usage_error(fmt::format("--k must lie in 1..{} for {} (got {})", set.table.k, points_file, k));
    } else if (width < 1 || height < 1 || width > 65536 || height > 65536) {
      throw usage_error(fmt::format("--width/--height must lie in 1..65536 (got {}x{})", width, height));
    }
    double gaze[2];
    fov::require_gaze("--gaze", gaze_text, display, gaze);

    const auto start = std::chrono::steady_clock::now();
    auto scene = fov::load_scene(scene_spec);
    for (const std::string& w : scene->warnings()) std::cerr << "fovrender: warning: " << w << "\n";
    fov::camera cam = scene->default_camera(hfov > 0 ? float(hfov) : 90.0f);
    if (hfov > 0) cam.hfov_deg = float(hfov);
    fov::trace_params tp;
    tp.spp = spp;
    tp.seed = seed;
    tp.shadows = !no_shadows;
    tp.footprint = footprint;

    json j;
    if (!no_warmup) {
      // Untimed: OpenImageIO reads textures and builds their MIP levels on first use, once
      // per process. The reference reads levels no coarser than a 1-spp full-resolution
      // pass builds; a foveated frame's wider footprints read coarser ones, which only the
      // same trace touches (after a 1-spp pass, a helmet frame at s = 1.75 still built levels:
      // 252 against 66 ms at 1 spp, 284 against 123 ms at 4 spp).
      const auto warm = std::chrono::steady_clock::now();
      if (reference) {
        fov::trace_params once = tp;
        once.spp = 1;
        fov::trace_reference(*scene, cam, display.width, display.height, once);
      } else {
        fov::trace_points(*scene, cam, set, gaze[0], gaze[1], k, tp);
      }
      j["warmup_ms"] = ms_since(warm);
    }
    fov::frame image;
    const auto traced = std::chrono::steady_clock::now();
    if (reference) {
      image = fov::trace_reference(*scene, cam, display.width, display.height, tp);
      j["trace_ms"] = ms_since(traced);
      j["reconstruct_ms"] = 0.0;
      j["rays"] = image.rays;
      j["points_traced"] = nullptr;
    } else {
      fov::reconstruct_params rp;
      rp.how = how;
      rp.k = k;
      rp.renka = renka;
      rp.kernel = kernel_text == "gaussian" ? fov::rbf_kernel::gaussian : fov::rbf_kernel::multiquadric;
      rp.shape = shape;
      fov::rbf_stats rbf;
      fov::rbf_stats* rbf_out = how == fov::method::rbf ? &rbf : nullptr;
      std::unique_ptr<fov::cl_reconstructor> device;
      std::unique_ptr<fov::rbf_weight_cache> cpu_cache;  // RBF on the C++ path
      if (device_text == "opencl") {
        const auto setup = std::chrono::steady_clock::now();
        device = std::make_unique<fov::cl_reconstructor>(set);
        j["device_setup_ms"] = ms_since(setup);
        if (!device->available()) std::cerr << "fovrender: warning: " << device->reason() << "; using the C++ path\n";
      }
      // With --taa-frames N: N frames of the same view blended by TAA, each with new ray
      // positions (--pattern reseed: seed + frame), or the set mirrored in turn (mirror:
      // four patterns), or the same samples (fixed: what the thesis's static view sees).
      // The JSON reports the last frame's costs.
      fov::taa_state taa;
      fov::point_samples samples;
      bool on_device = false;
      for (uint32_t frame_index = 0; frame_index < std::max<uint32_t>(1, taa_frames); ++frame_index) {
        fov::trace_params this_frame = tp;
        if (taa_frames > 0 && pattern == "reseed") this_frame.seed = seed + frame_index;
        if (taa_frames > 0 && pattern == "mirror") this_frame.mirror_x = frame_index & 1, this_frame.mirror_y = frame_index & 2;
        const auto traced_at = std::chrono::steady_clock::now();
        samples = fov::trace_points(*scene, cam, set, gaze[0], gaze[1], k, this_frame);
        j["trace_ms"] = ms_since(traced_at);
        if (frame_index == 0 && (how == fov::method::rbf || (device && device->available()))) {
          // The first launch compiles the kernel for its launch shape (PoCL) and, for RBF,
          // solves the weights of every canvas pixel the screen covers: reported apart, so
          // reconstruct_ms is what every later frame at this gaze costs. It also allocates
          // the frame the timed runs reuse, as a live loop does (allocating and first touching
          // a new FOVE frame inside the timed run cost about 50 ms here: docs/benchmarks.md).
          const auto first = std::chrono::steady_clock::now();
          if (device) {
            device->run(samples, rp, image);
          } else {
            cpu_cache = std::make_unique<fov::rbf_weight_cache>(set, rp);
            cpu_cache->prepare(samples.offset);
          }
          j["device_first_launch_ms"] = ms_since(first);
          if (how == fov::method::rbf)
            j["rbf_weights_ms"] = 1e3 * (device ? device->rbf_cache()->seconds() : cpu_cache->seconds());
        }
        const auto rebuilt = std::chrono::steady_clock::now();
        if (taa_frames > 0 && device && device->available()) {
          // Reconstruction and TAA on the device, the frame kept there in between; TAA's
          // share is its kernel's time.
          device->run_taa(samples, rp, taa, cam, gaze, {}, image, &on_device, rbf_out);
          j["taa_ms"] = device->last_taa_kernel_ms();
          j["reconstruct_ms"] = ms_since(rebuilt) - j["taa_ms"].get<double>();
        } else {
          if (device)
            device->run(samples, rp, image, &on_device, rbf_out);
          else
            image = fov::reconstruct(set, samples, rp, rbf_out, cpu_cache.get());
          j["reconstruct_ms"] = ms_since(rebuilt);
          if (taa_frames > 0) {
            const auto blended = std::chrono::steady_clock::now();
            image = fov::taa_resolve(taa, image, cam, display, gaze);
            j["taa_ms"] = ms_since(blended);
          }
        }
      }
      j["device"] = on_device ? device->device() : std::string("C++ (TBB)");
      if (how == fov::method::rbf)
        j["rbf"] = {{"kernel", kernel_text}, {"shape", shape}, {"fallbacks", rbf.fallbacks},
                    {"worst_condition", rbf.worst_condition}, {"condition_sampled_pixels", rbf.sampled}};
      j["rays"] = samples.rays;
      j["points_traced"] = samples.traced.size();
      if (taa_frames > 0) j["taa_frames"] = taa_frames, j["pattern"] = pattern;
    }
    if (!j.contains("taa_ms")) j["taa_ms"] = nullptr;  // no TAA in this run
    // A frame's cost: tracing, reconstruction and TAA (one-time device setup and scene loading are reported apart).
    j["total_ms"] = j["trace_ms"].get<double>() + j["reconstruct_ms"].get<double>() +
                    (j["taa_ms"].is_number() ? j["taa_ms"].get<double>() : 0.0);
    j["scene_load_ms"] = std::chrono::duration<double, std::milli>(traced - start).count();
    j["width"] = display.width;
    j["height"] = display.height;
    j["spp"] = spp;
    j["method"] = reference ? "reference" : fov::method_name(how);
    if (!reference) j["k"] = k, j["texture_footprint"] = fov::texture_footprint_name(footprint);

    for (const std::string& output : outputs) fov::write_frame(image, output);
    if (!debug_view.empty()) {
      if (debug_output.empty()) {
        const std::filesystem::path first(outputs.front());
        debug_output = (first.parent_path() / (first.stem().string() + "-" + debug_view)).string() + ".png";
      }
      fov::write_frame(fov::debug_overlay(debug_view, image, reference ? nullptr : &set, gaze), debug_output);
    }
    if (!compare.empty()) {
      const fov::frame ref = fov::read_frame(compare);
      if (ref.width != image.width || ref.height != image.height)
        throw usage_error(fmt::format("--compare {}: {}x{} does not match the {}x{} frame", compare, ref.width,
                                      ref.height, image.width, image.height));
      const fov::frame_comparison c = fov::compare_frames(image, ref, display, gaze[0], gaze[1]);
      j["metrics"] = {{"psnr", band_json(c.overall)["psnr"]}, {"ssim", c.overall.ssim},
                      {"psnr_fovea", band_json(c.fovea)["psnr"]}, {"ssim_fovea", c.fovea.ssim},
                      {"psnr_mid", band_json(c.mid)["psnr"]}, {"ssim_mid", c.mid.ssim},
                      {"psnr_periphery", band_json(c.periphery)["psnr"]}, {"ssim_periphery", c.periphery.ssim},
                      {"bands", {{"fovea", band_json(c.fovea)}, {"mid", band_json(c.mid)}, {"periphery", band_json(c.periphery)}}}};
    }
    if (as_json) {
      std::cout << j.dump(2) << "\n";
    } else {
      fmt::print("{} {}x{}: {} rays, trace {:.1f} ms, reconstruct {:.1f} ms\n", j["method"].get<std::string>(),
                 display.width, display.height, j["rays"].get<uint64_t>(), j["trace_ms"].get<double>(),
                 j["reconstruct_ms"].get<double>());
      if (j.contains("metrics")) {
        const json& m = j["metrics"];
        fmt::print("vs {}: PSNR {} dB, SSIM {:.4f} | fovea (<5 deg) {} dB {:.4f} | 5-30 deg {} dB {:.4f} | >30 deg {} dB {:.4f}\n",
                   compare, m["psnr"].dump(), m["ssim"].get<double>(), m["psnr_fovea"].dump(),
                   m["ssim_fovea"].get<double>(), m["psnr_mid"].dump(), m["ssim_mid"].get<double>(),
                   m["psnr_periphery"].dump(), m["ssim_periphery"].get<double>());
      }
    }
    return 0;
  });
}
