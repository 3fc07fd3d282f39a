#include "compare_command.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "cli.h"
#include "fov/colour.h"
#include "fov/usage_error.h"
#include "image_io.h"

namespace fov {

using json = nlohmann::json;

std::string frame_path(const std::string& flag, const std::string& pattern, int n, bool required) {
  std::string out;
  int conversions = 0;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%', ++i;
      continue;
    }
    int width = 0;
    size_t j = i + 1;
    if (j + 1 < pattern.size() && pattern[j] == '0' && std::isdigit(static_cast<unsigned char>(pattern[j + 1])))
      width = pattern[j + 1] - '0', j += 2;
    if (j >= pattern.size() || pattern[j] != 'd')
      throw usage_error(fmt::format("{} {}: only %d or %0Nd may number the frames", flag, pattern));
    out += fmt::format("{:0{}d}", n, width);
    ++conversions;
    i = j;
  }
  if (conversions > 1) throw usage_error(fmt::format("{} {}: one %d numbers the frames, not {}", flag, pattern, conversions));
  if (required && conversions == 0) throw usage_error(fmt::format("{} {}: with --fps, name the frames with %d or %0Nd", flag, pattern));
  return out;
}

namespace {

json photometry_json(const display_photometry& p) {
  return {{"peak_luminance", p.peak}, {"contrast", p.contrast}, {"ambient_lux", p.ambient_lux}, {"black_level", p.black()}};
}

// `fovbench compare --fps`: FovVideoVDP over the frames, one gaze.
// --display (with --viewing-distance), or the images' size seen from one width (or from
// --viewing-distance).
display_geometry display_for(const compare_options& o, int width, int height) {
  if (!o.display.empty()) return require_display("--display", o.display, o.viewing_distance);
  display_geometry display{width, height, 1.0};
  if (o.viewing_distance != 0) {
    if (const std::string why = viewing_distance_problem(o.viewing_distance); !why.empty()) throw usage_error("--viewing-distance: " + why);
    display.viewing_distance = o.viewing_distance;
  }
  return display;
}

std::string run_compare_video(const compare_options& o) {
  if (o.frames < 1 || o.frames > 100000) throw usage_error("--frames must lie in 1..100000 with --fps");
  if (!(o.fps >= 8 && o.fps <= 1000)) throw usage_error("--fps must lie in 8..1000");
  if (!o.jod) throw usage_error("--no-jod: a video comparison measures JOD only");
  if (!o.flip_map.empty() || !o.foveated_flip_map.empty()) throw usage_error("--flip-map and --foveated-flip-map are for images");
  const bool still = o.reference.find('%') == std::string::npos;
  frame_path("test", o.test, 0, true);
  frame_path("reference", o.reference, 0, false);
  const frame first = read_frame(frame_path("test", o.test, 0, true));
  const display_geometry display = display_for(o, first.width, first.height);
  if (display.width != first.width || display.height != first.height)
    throw usage_error(fmt::format("--display is {}x{}, the frames {}x{}", display.width, display.height, first.width, first.height));
  if (display.width < 8 || display.height < 8) throw usage_error("JOD needs frames of at least 8x8 pixels");
  const gaze_point gaze = require_gaze("--gaze", o.gaze, display);
  fvvdp metric(display, o.fps, o.photometry);
  frame reference;
  for (int n = 0; n < o.frames; ++n) {
    const std::string test_path = frame_path("test", o.test, n, true);
    const frame test = n == 0 ? first : read_frame(test_path);
    if (n == 0 || !still) reference = read_frame(frame_path("reference", o.reference, n, false));
    for (const auto& [path, f] : {std::pair<std::string, const frame*>{test_path, &test}, {o.reference, &reference}})
      if (f->width != display.width || f->height != display.height)
        throw usage_error(fmt::format("{} is {}x{}, the first frame {}x{}", path, f->width, f->height, display.width, display.height));
    metric.add(test, reference, gaze);
  }
  const fvvdp_result r = metric.result();
  if (!o.json)
    return fmt::format("vs {}: video JOD {:.3f} foveated at the gaze, {:.3f} non-foveated, {} frames at {:g} fps (FovVideoVDP: "
                       "10 = no visible difference, 1 JOD apart = 75 % of observers prefer the better)\n",
                       o.reference, r.jod, r.jod_nonfoveated, r.frames, o.fps);
  json j{{"test", o.test}, {"reference", o.reference}, {"jod", r.jod}, {"jod_nonfoveated", r.jod_nonfoveated},
         {"frames", r.frames}, {"fps", o.fps}, {"gaze", {gaze.x, gaze.y}},
         {"display", {{"width", display.width}, {"height", display.height}, {"viewing_distance", display.viewing_distance}}},
         {"photometry", photometry_json(o.photometry)}};
  return j.dump(2) + "\n";
}

}  // namespace

std::string run_compare(const compare_options& o) {
  if (o.fps != 0 || o.frames != 0) {
    if (o.fps == 0) throw usage_error("--frames needs --fps");
    return run_compare_video(o);
  }
  const bool named = !o.display.empty();
  display_geometry display = display_for(o, 0, 0);
  if (!o.flip && !(o.flip_map.empty() && o.foveated_flip_map.empty()))
    throw usage_error("--no-flip leaves no FLIP map to write");
  // The maps are checked before anything is read: neither may be an input (or each other).
  require_output("--flip-map", o.flip_map, {o.test, o.reference});
  require_output("--foveated-flip-map", o.foveated_flip_map, {o.test, o.reference});
  if (!o.flip_map.empty() && o.flip_map == o.foveated_flip_map)
    throw usage_error("--flip-map and --foveated-flip-map name the same file");
  const frame test = read_frame(o.test), reference = read_frame(o.reference);
  if (test.width != reference.width || test.height != reference.height)
    throw usage_error(fmt::format("{} is {}x{} but {} is {}x{}", o.test, test.width, test.height, o.reference, reference.width,
                                  reference.height));
  if (!named) display.width = test.width, display.height = test.height;
  if (display.width != test.width || display.height != test.height)
    throw usage_error(fmt::format("--display {} is {}x{}, the images {}x{}", o.display, display.width, display.height,
                                  test.width, test.height));
  const gaze_point gaze = require_gaze("--gaze", o.gaze, display);
  spacing_model eye;
  eye.display = display;
  comparison_params what;
  what.flip = o.flip, what.jod = o.jod, what.photometry = o.photometry;
  what.keep_maps = !o.flip_map.empty() || !o.foveated_flip_map.empty();
  const comparison c = compare_images(test, reference, eye, gaze, what);
  if (!o.flip_map.empty()) write_error_map(c.flip.flip_map, o.flip_map);
  if (!o.foveated_flip_map.empty()) write_error_map(c.flip.foveated_map, o.foveated_flip_map);
  if (!o.json) return comparison_text(c, o.reference) + "\n";
  json j = comparison_json(c);
  j["test"] = o.test, j["reference"] = o.reference;
  j["display"] = {{"width", display.width}, {"height", display.height}, {"viewing_distance", display.viewing_distance}};
  if (c.has_jod) j["photometry"] = photometry_json(o.photometry);
  j["gaze"] = {gaze.x, gaze.y};
  return j.dump(2) + "\n";
}

void add_photometry_flags(CLI::App& app, display_photometry& p) {
  auto in_range = [](double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
          const double v = std::strtod(text.c_str(), nullptr);
          if (std::isfinite(v) && v >= lo && v <= hi) return "";
          return fmt::format("must lie in {:g}..{:g}", lo, hi);
        },
        fmt::format("{:g}..{:g}", lo, hi));
  };
  app.add_option("--peak-luminance", p.peak, "JOD: the display's peak luminance, cd/m^2")
      ->check(in_range(0.1, 10000))
      ->capture_default_str();
  app.add_option("--contrast", p.contrast, "JOD: the display's contrast, peak : black in the dark")
      ->check(in_range(2, 1e6))
      ->capture_default_str();
  app.add_option("--ambient", p.ambient_lux, "JOD: ambient light on the screen, lux (reflected at 0.5 %)")
      ->check(in_range(0, 1e5))
      ->capture_default_str();
}

void write_error_map(const error_map& map, const std::string& path) {
  frame f;
  f.width = map.width, f.height = map.height;
  f.rgb.reserve(map.value.size());
  // write_frame sRGB-encodes: decoding first makes the stored byte the error itself.
  for (float v : map.value) f.rgb.emplace_back(srgb_decode(std::clamp(v, 0.0f, 1.0f)));
  write_frame(f, path);
}

}  // namespace fov
