#include "fov/lattice.h"

#include <cmath>
#include <stdexcept>

#include "fov/dart_throwing.h"

namespace fov {

namespace {
constexpr double pi = 3.14159265358979323846;

// The farthest a canvas point lies from the centre: the canvas corner.
double corner_px(const spacing_model& model) {
  return std::hypot(double(model.display.width), double(model.display.height));
}
}  // namespace

double lattice_pitch_px(const spacing_model& model, double distance_px) {
  const double fd = display_nyquist_cpd(model.display);
  return fd / std::min(fd, cutoff_frequency_cpd(model.acuity, eccentricity_deg(model, distance_px)));
}

std::vector<double> lattice_rings(const spacing_model& model, point_sampler sampler) {
  const double corner = corner_px(model);
  std::vector<double> rings;
  if (sampler == point_sampler::polar) {
    for (double r = lattice_pitch_px(model, 0.0);; r += lattice_pitch_px(model, r)) {
      rings.push_back(r);
      if (r > corner) break;
    }
    return rings;
  }
  if (sampler != point_sampler::log_polar) throw std::invalid_argument("lattice_rings: not a lattice sampler");
  // u(r) by Simpson's rule on steps of at most a tenth of a pixel (the pitch is at least one
  // pixel and changes slowly), each ring found by linear interpolation within its step.
  const double h = 0.1;
  double r = 0, u = 0;
  for (double next_ring = 1;; r += h) {
    const double du = h / 6 * (1 / lattice_pitch_px(model, r) + 4 / lattice_pitch_px(model, r + h / 2) +
                                1 / lattice_pitch_px(model, r + h));
    while (u + du >= next_ring) {
      rings.push_back(r + h * (next_ring - u) / du);
      if (rings.back() > corner) return rings;
      next_ring += 1;
    }
    u += du;
  }
}

uint32_t lattice_ring_count(const spacing_model& model, double radius_px) {
  const double n = 2 * pi * radius_px / lattice_pitch_px(model, radius_px);
  return uint32_t(std::ceil(n - 1e-9));
}

std::vector<point> lattice_points(const spacing_model& model, point_sampler sampler) {
  const double cx = model.display.width, cy = model.display.height;
  const double w = 2.0 * model.display.width, h = 2.0 * model.display.height;
  std::vector<point> points;
  points.push_back({float(cx), float(cy), float(lattice_pitch_px(model, 0.0))});
  for (double r : lattice_rings(model, sampler)) {
    const uint32_t n = lattice_ring_count(model, r);
    const double q = lattice_pitch_px(model, r);
    // polar: n equal steps, half a step from angle 0; log-polar: steps of the pitch from 0.
    const double step = sampler == point_sampler::polar ? 2 * pi / n : q / r, phase = sampler == point_sampler::polar ? 0.5 : 0.0;
    for (uint32_t i = 0; i < n; ++i) {
      const double a = (i + phase) * step;
      const float x = float(cx + r * std::cos(a)), y = float(cy + r * std::sin(a));
      if (x >= 0 && y >= 0 && x < float(w) && y < float(h)) points.push_back({x, y, float(q)});
    }
  }
  sort_morton(points);
  return points;
}

}  // namespace fov
