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
#include "../common/debug_views.h"
#include "../common/image_io.h"
#include "../common/render_flags.h"
#include "fov/metrics.h"
#include "fov/pointset_io.h"
#include "fov/renderer.h"

namespace {

using json = nlohmann::json;
using fov::usage_error;

// What fovrender does beyond the render parameters.
struct render_options {
  std::string scene = "builtin", points, gaze = "centre", compare, debug_output;
  std::vector<std::string> outputs;
  fov::debug_view debug = fov::debug_view::points;
  bool debug_asked = false;  // --debug-view given
  bool reference = false, no_warmup = false, json = false;
  int width = 1280, height = 1440;  // without --points
  uint32_t taa_frames = 0;
};

json band_json(const fov::band_metrics& m) {
  return {{"psnr", std::isfinite(m.psnr) ? json(m.psnr) : json("inf")}, {"ssim", m.ssim}, {"pixels", m.pixels}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fovrender: render one frame foveated (or at full resolution) and measure it"};
  render_options o;
  fov::render_params p;
  app.add_option("--scene", o.scene, "builtin, a glTF/OBJ file, or env:IMAGE");
  app.add_option("--points", o.points, "Point set (.fovset); gives the screen size");
  app.add_option("--gaze", o.gaze, "X,Y in screen pixels, centre or corner");
  fov::add_render_flags(app, p);
  app.add_flag("--reference", o.reference, "Render at full resolution instead");
  app.add_option("--width", o.width, "Screen width without --points")->check(CLI::Range(1, 65536));
  app.add_option("--height", o.height, "Screen height without --points")->check(CLI::Range(1, 65536));
  app.add_option("--taa-frames", o.taa_frames, "Render this many frames of the view with TAA (--pattern)")
      ->check(CLI::Range(0u, 10000u));
  app.add_flag("--no-warmup", o.no_warmup,
               "Time the very first frame: texture loading, kernel compilation and RBF weights included");
  app.add_option("-o,--output", o.outputs, "Output image (.exr linear, .png sRGB); may be repeated");
  CLI::Option* debug = fov::add_label_option(app, "--debug-view", o.debug, fov::debug_view_labels,
                                               "Write that overlay too (none unless given)", false);
  app.add_option("--debug-output", o.debug_output, "File for the overlay (default: the first -o with '-VIEW' before the extension)");
  app.add_option("--compare", o.compare, "Reference image: print PSNR/SSIM overall and by eccentricity band");
  app.add_flag("--json", o.json, "Print JSON");
  return fov::run_tool("fovrender", app, argc, argv, [&] {
    o.debug_asked = debug->count() > 0;
    if (o.outputs.empty() && o.compare.empty()) throw usage_error("nothing to do: give -o and/or --compare");
    if (o.debug_asked && o.debug_output.empty() && o.outputs.empty()) throw usage_error("--debug-view needs -o or --debug-output");
    if (!o.reference && o.points.empty()) throw usage_error("--points is required unless --reference");
    if (o.reference && o.taa_frames > 0) throw usage_error("--taa-frames applies to foveated frames, not --reference");
    p.taa = o.taa_frames > 0;

    fov::require_valid(p);  // what does not depend on the set, before loading it
    std::shared_ptr<const fov::pointset> set;
    fov::display_geometry display{o.width, o.height, 1.0};
    if (!o.points.empty()) {
      set = std::make_shared<const fov::pointset>(fov::load_pointset(o.points));
      display = set->model.display;
    }
    const std::string problem = fov::validate(p, set.get());
    if (!problem.empty()) throw usage_error(set ? fmt::format("{} for {}", problem, o.points) : problem);
    const fov::gaze_point gaze = fov::require_gaze("--gaze", o.gaze, display);

    json j;
    const auto loading = std::chrono::steady_clock::now();
    std::shared_ptr<const fov::scene> scene = fov::load_scene(o.scene);
    j["scene_load_ms"] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - loading).count();
    for (const std::string& w : scene->warnings()) std::cerr << "fovrender: warning: " << w << "\n";
    fov::renderer r(scene, p);
    fov::frame image;
    fov::frame_timing t;
    if (o.reference) {
      if (!o.no_warmup) j["warmup_ms"] = r.warm_up_reference(display.width, display.height, p).trace_ms;
      image = r.reference(display.width, display.height, p, &t).image;
    } else {
      r.use_pointset(set);
      if (p.device == fov::reconstruct_device::opencl) j["device_setup_ms"] = r.device_setup_ms();
      if (const std::string w = r.device_warning(); !w.empty()) std::cerr << "fovrender: " << w << "\n";
      if (!o.no_warmup) {
        const fov::warm_up_report w = r.warm_up(gaze, p);
        j["warmup_ms"] = w.trace_ms;
        j["device_first_launch_ms"] = w.reconstruct_ms;
        if (p.reconstruct.how == fov::method::rbf) j["rbf_weights_ms"] = w.rbf_weights_ms;
      }
      // With --taa-frames N: N frames of the same view blended by TAA; the JSON reports the last frame's costs.
      const fov::frame* last = nullptr;  // the renderer's frame, valid until its next call
      for (uint32_t n = 0; n < std::max<uint32_t>(1, o.taa_frames); ++n) last = &r.foveated(gaze, p, &t);
      image = *last;
      j["device"] = r.device();
      if (p.reconstruct.how == fov::method::rbf)
        j["rbf"] = {{"kernel", fov::label_of(fov::rbf_kernel_labels, p.reconstruct.kernel)}, {"shape", p.reconstruct.shape},
                    {"fallbacks", t.rbf.fallbacks}, {"worst_condition", t.rbf.worst_condition},
                    {"condition_sampled_pixels", t.rbf.sampled}};
      if (p.taa) j["taa_frames"] = o.taa_frames, j["pattern"] = fov::label_of(fov::ray_pattern_labels, p.pattern);
      j["k"] = p.reconstruct.k;
      j["texture_footprint"] = fov::texture_footprint_name(p.footprint);
    }
    // A frame's cost: tracing, reconstruction and TAA (setup, loading and warm-up are reported apart).
    j["trace_ms"] = t.trace_ms;
    j["reconstruct_ms"] = t.reconstruct_ms;
    j["taa_ms"] = p.taa ? json(t.taa_ms) : json(nullptr);
    j["total_ms"] = t.total_ms();
    j["rays"] = t.rays;
    j["points_traced"] = o.reference ? json(nullptr) : json(t.points_traced);
    j["width"] = display.width;
    j["height"] = display.height;
    j["spp"] = p.spp;
    j["method"] = o.reference ? "reference" : fov::method_name(p.reconstruct.how);

    for (const std::string& output : o.outputs) fov::write_frame(image, output);
    if (o.debug_asked) {
      const char* view = fov::label_of(fov::debug_view_labels, o.debug);
      if (o.debug_output.empty()) {
        const std::filesystem::path first(o.outputs.front());
        o.debug_output = (first.parent_path() / (first.stem().string() + "-" + view)).string() + ".png";
      }
      fov::write_frame(fov::debug_overlay(o.debug, image, o.reference ? nullptr : set.get(), gaze), o.debug_output);
    }
    if (!o.compare.empty()) {
      const fov::frame ref = fov::read_frame(o.compare);
      if (ref.width != image.width || ref.height != image.height)
        throw usage_error(fmt::format("--compare {}: {}x{} does not match the {}x{} frame", o.compare, ref.width,
                                      ref.height, image.width, image.height));
      const fov::frame_comparison c = fov::compare_frames(image, ref, display, gaze);
      j["metrics"] = {{"psnr", band_json(c.overall)["psnr"]}, {"ssim", c.overall.ssim},
                      {"psnr_fovea", band_json(c.fovea)["psnr"]}, {"ssim_fovea", c.fovea.ssim},
                      {"psnr_mid", band_json(c.mid)["psnr"]}, {"ssim_mid", c.mid.ssim},
                      {"psnr_periphery", band_json(c.periphery)["psnr"]}, {"ssim_periphery", c.periphery.ssim},
                      {"bands", {{"fovea", band_json(c.fovea)}, {"mid", band_json(c.mid)}, {"periphery", band_json(c.periphery)}}}};
    }
    if (o.json) {
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    fmt::print("{} {}x{}: {} rays, trace {:.1f} ms, reconstruct {:.1f} ms\n", j["method"].get<std::string>(), display.width,
               display.height, t.rays, t.trace_ms, t.reconstruct_ms);
    if (j.contains("metrics")) {
      const json& m = j["metrics"];
      fmt::print("vs {}: PSNR {} dB, SSIM {:.4f} | fovea (<5 deg) {} dB {:.4f} | 5-30 deg {} dB {:.4f} | >30 deg {} dB {:.4f}\n",
                 o.compare, m["psnr"].dump(), m["ssim"].get<double>(), m["psnr_fovea"].dump(), m["ssim_fovea"].get<double>(),
                 m["psnr_mid"].dump(), m["ssim_mid"].get<double>(), m["psnr_periphery"].dump(),
                 m["ssim_periphery"].get<double>());
    }
    return 0;
  });
}
