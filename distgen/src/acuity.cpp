#include "fov/acuity.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace fov {

namespace {
constexpr double pi = 3.14159265358979323846;
}

const char* acuity_model_name(acuity_model model) {
  for (const auto& [label, value] : acuity_model_labels)
    if (value == model) return label;
  return "unknown";
}

bool same_acuity(const acuity_params& a, const acuity_params& b) {
  if (a.model != b.model) return false;
  switch (a.model) {
    case acuity_model::wang_csf: return a.ct0 == b.ct0 && a.alpha == b.alpha && a.e2 == b.e2;
    case acuity_model::linear_mar:
      return a.mar_slope == b.mar_slope && a.mar_fovea_deg == b.mar_fovea_deg && a.mar_dead_zone_deg == b.mar_dead_zone_deg;
    case acuity_model::piecewise_mar:
      return std::equal(std::begin(a.pivot_cpd), std::end(a.pivot_cpd), std::begin(b.pivot_cpd));
  }
  return true;
}

std::string acuity_label(const acuity_params& acuity) {
  std::string label = acuity_model_name(acuity.model);
  acuity_params defaults;
  defaults.model = acuity.model;
  if (same_acuity(acuity, defaults)) return label;
  switch (acuity.model) {
    case acuity_model::wang_csf:
      return fmt::format("{}-c{:.4g}-a{:.4g}-e{:.4g}", label, acuity.ct0, acuity.alpha, acuity.e2);
    case acuity_model::linear_mar:
      return fmt::format("{}-m{:.4g}-w{:.4g}-d{:.4g}", label, acuity.mar_slope, acuity.mar_fovea_deg,
                         acuity.mar_dead_zone_deg);
    case acuity_model::piecewise_mar:
      return fmt::format("{}-f{:.4g}", label, fmt::join(acuity.pivot_cpd, "-"));
  }
  return label;
}

double eccentricity_deg(const spacing_model& model, double distance_px) {
  const double n_v = double(model.display.width) * model.display.viewing_distance;
  return model.scale * std::atan(distance_px / n_v) * (180.0 / pi);
}

double cutoff_frequency_cpd(const acuity_params& acuity, double eccentricity) {
  switch (acuity.model) {
    case acuity_model::wang_csf:
      return acuity.e2 * std::log(1.0 / acuity.ct0) / ((eccentricity + acuity.e2) * acuity.alpha);
    case acuity_model::linear_mar: {
      const double mar = acuity.mar_slope * std::max(eccentricity - acuity.mar_dead_zone_deg, 0.0) + acuity.mar_fovea_deg;
      return 1.0 / (2.0 * mar);
    }
    case acuity_model::piecewise_mar: {
      // The segment holding e (the last one beyond 60 degrees), its MAR 1/f linear in e.
      const double* e = piecewise_pivots_deg;
      const double* f = acuity.pivot_cpd;
      size_t i = 0;
      while (i + 2 < std::size(piecewise_pivots_deg) && eccentricity >= e[i + 1]) ++i;
      const double t = (eccentricity - e[i]) / (e[i + 1] - e[i]);
      const double mar = (1.0 / f[i]) + t * (1.0 / f[i + 1] - 1.0 / f[i]);
      return 1.0 / mar;
    }
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
    case acuity_model::linear_mar:
      if (!(m.acuity.mar_slope > 0 && m.acuity.mar_slope <= max_mar_slope))
        return fmt::format("MAR slope must lie in (0, {}] (got {})", max_mar_slope, m.acuity.mar_slope);
      if (!(m.acuity.mar_fovea_deg >= min_mar_fovea_deg && m.acuity.mar_fovea_deg <= max_mar_fovea_deg))
        return fmt::format("foveal MAR must lie in {:.4g}..{} degrees (got {})", min_mar_fovea_deg, max_mar_fovea_deg,
                           m.acuity.mar_fovea_deg);
      if (!(m.acuity.mar_dead_zone_deg >= 0 && m.acuity.mar_dead_zone_deg <= max_mar_dead_zone_deg))
        return fmt::format("MAR dead zone must lie in 0..{} degrees (got {})", max_mar_dead_zone_deg,
                           m.acuity.mar_dead_zone_deg);
      break;
    case acuity_model::piecewise_mar:
      for (size_t i = 0; i < std::size(m.acuity.pivot_cpd); ++i) {
        const double f = m.acuity.pivot_cpd[i];
        if (!(f >= min_pivot_cpd && f <= max_pivot_cpd))
          return fmt::format("acuity at {} degrees must lie in {}..{} cycles per degree (got {})", piecewise_pivots_deg[i],
                             min_pivot_cpd, max_pivot_cpd, f);
        if (i > 0 && f > m.acuity.pivot_cpd[i - 1])
          return fmt::format("acuity must not grow with eccentricity ({} cpd at {} degrees, {} at {})",
                             m.acuity.pivot_cpd[i - 1], piecewise_pivots_deg[i - 1], f, piecewise_pivots_deg[i]);
      }
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
