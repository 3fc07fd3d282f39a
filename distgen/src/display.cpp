#include "fov/display.h"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace fov {

namespace {
constexpr double pi = 3.14159265358979323846;
constexpr double deg = pi / 180;

// The figures and their sources are in docs/displays.md; a preset's geometry never changes
// (its name is in set files), so a corrected figure becomes a new preset.
const std::vector<display_preset_info> presets = {
    {"fove", 1280, 1440, 1.0, 0, "FOVE 0, one eye of its 2560x1440 panel, seen from one width (the thesis)"},
    {"vive", 1080, 1200, 1.0, 0, "HTC Vive, one eye, seen from one width (the thesis's convention)"},
    {"desktop1080", 1920, 1080, 1.0, 0, "a 1080p monitor seen from one display width"},
    {"quest3", 2064, 2208, 0, 25, "Meta Quest 3, one eye; 25 ppd (iFixit's estimate, 2024)"},
    {"vision-pro", 3660, 3200, 0, 34, "Apple Vision Pro, one eye (iFixit's measured panel); 34 ppd (iFixit's estimate)"},
    {"varjo-xr4", 3840, 3744, 0, 51, "Varjo XR-4, one eye; 51 ppd (Varjo's figure)"},
    {"retinal", 3840, 3840, 0, 70, "a foveal-acuity panel: 70 ppd, past the 60 ppd that one arcminute resolves"},
};

std::string forms() {
  return fmt::format("{}, or WxH, WxH@Nppd, WxH@Ndeg, WxH@V (sides {}..{})", display_preset_names(), min_display_side,
                     max_display_side);
}

// A whole positive number with nothing else, or -1.
long whole(const std::string& s) {
  if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::strtol(s.c_str(), nullptr, 10);
}

// A finite positive decimal with nothing else, or NaN.
double decimal(const std::string& s) {
  if (s.empty() || s.find_first_not_of("0123456789.") != std::string::npos) return NAN;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  return (*end == '\0' && std::isfinite(v) && v > 0) ? v : NAN;
}
}  // namespace

std::string viewing_distance_problem(double v) {
  if (v >= min_viewing_distance && v <= max_viewing_distance) return "";
  return fmt::format("viewing distance must lie in {}..{} display widths (got {:.4g})", min_viewing_distance,
                     max_viewing_distance, v);
}

double pixel_eccentricity_deg(const display_geometry& d, gaze_point gaze, int x, int y) {
  const double dist = std::hypot(x + 0.5 - gaze.x, y + 0.5 - gaze.y);
  return std::atan(dist / (double(d.width) * d.viewing_distance)) / deg;
}

double pixels_per_degree(const display_geometry& d) { return double(d.width) * d.viewing_distance * deg; }
double horizontal_fov_deg(const display_geometry& d) { return 2 * std::atan(0.5 / d.viewing_distance) / deg; }
double vertical_fov_deg(const display_geometry& d) {
  return 2 * std::atan(0.5 * d.height / (double(d.width) * d.viewing_distance)) / deg;
}
double viewing_distance_for_ppd(int width, double ppd) { return ppd / (double(width) * deg); }
double viewing_distance_for_fov(double fov_deg) { return 0.5 / std::tan(0.5 * fov_deg * deg); }

display_geometry display_preset_info::geometry() const {
  return {width, height, ppd > 0 ? viewing_distance_for_ppd(width, ppd) : viewing_distance};
}

const std::vector<display_preset_info>& display_presets() { return presets; }

std::string display_preset_names() {
  std::string names;
  for (const display_preset_info& p : presets) names += std::string(names.empty() ? "" : ", ") + p.name;
  return names;
}

bool display_preset(const std::string& name, display_geometry& out) {
  for (const display_preset_info& p : presets)
    if (name == p.name) {
      out = p.geometry();
      return true;
    }
  return false;
}

std::string parse_display(const std::string& text, display_geometry& out) {
  if (display_preset(text, out)) return "";
  const std::string why = fmt::format("'{}' is not a display: {}", text, forms());
  const size_t x = text.find('x'), at = text.find('@');
  if (x == std::string::npos || (at != std::string::npos && at < x)) return why;
  const long w = whole(text.substr(0, x)), h = whole(text.substr(x + 1, at == std::string::npos ? std::string::npos : at - x - 1));
  if (w < 0 || h < 0) return why;
  if (w < min_display_side || h < min_display_side || w > max_display_side || h > max_display_side)
    return fmt::format("'{}': screen sides must lie in {}..{} pixels", text, min_display_side, max_display_side);
  display_geometry d{int(w), int(h), 1.0};
  if (at != std::string::npos) {
    const std::string rest = text.substr(at + 1);
    auto ends = [&](const char* unit) {
      const std::string u = unit;
      return rest.size() > u.size() && rest.compare(rest.size() - u.size(), u.size(), u) == 0;
    };
    if (ends("ppd")) {
      const double ppd = decimal(rest.substr(0, rest.size() - 3));
      if (std::isnan(ppd)) return why;
      d.viewing_distance = viewing_distance_for_ppd(d.width, ppd);
    } else if (ends("deg")) {
      const double fov = decimal(rest.substr(0, rest.size() - 3));
      if (std::isnan(fov)) return why;
      if (!(fov < 180)) return fmt::format("'{}': a field of view must be under 180 degrees", text);
      d.viewing_distance = viewing_distance_for_fov(fov);
    } else {
      d.viewing_distance = decimal(rest);
      if (std::isnan(d.viewing_distance)) return why;
    }
    if (const std::string far = viewing_distance_problem(d.viewing_distance); !far.empty())
      return fmt::format("'{}': {}", text, far);
  }
  out = d;
  return "";
}

std::string display_name(const display_geometry& d) {
  for (const display_preset_info& p : presets) {
    const display_geometry g = p.geometry();
    if (g.width == d.width && g.height == d.height && g.viewing_distance == d.viewing_distance) return p.name;
  }
  return fmt::format("{}x{}-v{:.4g}", d.width, d.height, d.viewing_distance);
}

}  // namespace fov
