#include "fov/acuity.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace fov {

namespace {
constexpr double pi = 3.14159265358979323846;
}

const char* acuity_model_name(acuity_model model) {
  switch (model) {
    case acuity_model::wang_csf: return "wang_csf";
  }
  return "unknown";
}

double eccentricity_deg(const spacing_model& model, double distance_px) {
  const double n_v = double(model.display.width) * model.display.viewing_distance;
  return model.scale * std::atan(distance_px / n_v) * (180.0 / pi);
}

double cutoff_frequency_cpd(const acuity_params& acuity, double eccentricity) {
  switch (acuity.model) {
    case acuity_model::wang_csf:
      return acuity.e2 * std::log(1.0 / acuity.ct0) / ((eccentricity + acuity.e2) * acuity.alpha);
  }
  return 0.0;
}

double display_nyquist_cpd(const display_geometry& display) {
  return pi * double(display.width) * display.viewing_distance / 360.0;
}

double point_spacing_px(const spacing_model& model, double distance_px) {
  const double fd = display_nyquist_cpd(model.display);
  const double fc = cutoff_frequency_cpd(model.acuity, eccentricity_deg(model, distance_px));
  const double fc0 = std::min(fd, fc);
  const double a = std::sqrt(1.0 / pi);
  return fd / fc0 - (1.0 - a);
}

std::string validate(const spacing_model& m) {
  if (m.display.width <= 0) return fmt::format("width must be positive (got {})", m.display.width);
  if (m.display.height <= 0) return fmt::format("height must be positive (got {})", m.display.height);
  if (m.display.width > 65536 || m.display.height > 65536)
    return fmt::format("screen {}x{} is larger than the supported 65536 pixels a side",
                       m.display.width, m.display.height);
  if (std::string why = viewing_distance_problem(m.display.viewing_distance); !why.empty()) return why;
  if (!(m.scale > 0) || !std::isfinite(m.scale))
    return fmt::format("scale must be positive (got {})", m.scale);
  switch (m.acuity.model) {
    case acuity_model::wang_csf:
      if (!(m.acuity.ct0 > 0 && m.acuity.ct0 < 1)) return "CSF CT0 must lie in (0, 1)";
      if (!(m.acuity.alpha > 0) || !std::isfinite(m.acuity.alpha)) return "CSF alpha must be positive";
      if (!(m.acuity.e2 > 0) || !std::isfinite(m.acuity.e2)) return "CSF e2 must be positive";
      break;
    default:
      return fmt::format("unknown acuity model {}", uint32_t(m.acuity.model));
  }
  // Dart throwing needs spacing that never shrinks away from the gaze.
  const double corner_d = std::hypot(double(m.display.width), double(m.display.height));
  double previous = point_spacing_px(m, 0.0);
  for (int i = 1; i <= 1024; ++i) {
    const double p = point_spacing_px(m, corner_d * i / 1024.0);
    if (p < previous * (1 - 1e-12))
      return fmt::format("acuity model {} gives spacing that shrinks with eccentricity",
                         acuity_model_name(m.acuity.model));
    previous = p;
  }
  // The largest spacing on the canvas must be finite and the smallest positive.
  const double corner = std::hypot(double(m.display.width), double(m.display.height));
  const double p0 = point_spacing_px(m, 0.0), p1 = point_spacing_px(m, corner);
  if (!std::isfinite(p0) || !std::isfinite(p1) || !(p0 > 0))
    return fmt::format("model gives unusable spacing ({:.4g} .. {:.4g} px)", p0, p1);
  if (p1 > 0.25 * double(std::max(m.display.width, m.display.height)) && p1 > 64.0)
    return fmt::format("spacing reaches {:.4g} px at the canvas corner, more than a quarter of the screen; "
                       "lower the scale or viewing distance", p1);
  return {};
}

}  // namespace fov
