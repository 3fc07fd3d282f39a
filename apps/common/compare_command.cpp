#include "compare_command.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "cli.h"
#include "fov/colour.h"
#include "fov/usage_error.h"
#include "image_io.h"

namespace fov {

using json = nlohmann::json;

std::string run_compare(const compare_options& o) {
  const bool named = !o.display.empty();
  display_geometry display = named ? parse_display(o.display) : display_geometry{};
  if (o.viewing_distance != 0) {
    if (const std::string why = viewing_distance_problem(o.viewing_distance); !why.empty()) throw usage_error("--viewing-distance: " + why);
    display.viewing_distance = o.viewing_distance;
  }
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
  if (c.has_jod)
    j["photometry"] = {{"peak_luminance", o.photometry.peak}, {"contrast", o.photometry.contrast},
                       {"ambient_lux", o.photometry.ambient_lux}, {"black_level", o.photometry.black()}};
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
