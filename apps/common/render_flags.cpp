#include "render_flags.h"

#include <sstream>

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
    add_label_option(app, "--texture-footprint", p.footprint, texture_footprint_labels,
                     "Foveated rays filter textures over their share of the point's disc (disc: the thesis's "
                     "prefilter) or of a pixel (pixel: sharper, cheaper, aliased periphery)");
    app.add_option("--exposure", p.exposure_ev, "Exposure in EV: every colour times 2^EV, then clamped for display")
        ->capture_default_str();
    app.add_option_function<std::string>(
        "--sun-dir", [&p](const std::string& t) { p.sun_direction = parse_triple("--sun-dir", t); },
        "Replace the scene's light by a sun in direction X,Y,Z (towards the light)");
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
        "Replace the scene's light by a sun of this irradiance (V or R,G,B; white albedo facing it: V + ambient)");
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
    app.add_option_function<std::string>(
           "--camera",
           [&p](const std::string& file) {
             const camera_path path = load_camera_path(file);  // first row: a still camera
             p.view.eye = glm::vec3(float(path.keys[0].eye[0]), float(path.keys[0].eye[1]), float(path.keys[0].eye[2]));
             p.view.target =
                 glm::vec3(float(path.keys[0].target[0]), float(path.keys[0].target[1]), float(path.keys[0].target[2]));
           },
           "A camera path CSV t_ms,x,y,z,tx,ty,tz (docs/fovview.md): its first row's eye and target")
        ->excludes(eye)
        ->excludes(target);
  }
}

void require_valid(const render_params& p, const pointset* set) {
  const std::string problem = validate(p, set);
  if (!problem.empty()) throw usage_error(problem);
}

}  // namespace fov
