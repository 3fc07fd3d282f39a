// Eccentricity bands over a screen seen with a gaze: the one place that decides which band
// a pixel falls in, for the metrics, geometry coverage and FLIP's pooling.
#pragma once

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <utility>
#include <vector>

#include "fov/acuity.h"

namespace fov {

// Bands [0, e0), [e0, e1), ..., [e_last, inf) of eccentricity in degrees, e = the edges.
class eccentricity_bands {
 public:
  // Throws std::invalid_argument when the edges do not increase.
  eccentricity_bands(const display_geometry& display, gaze_point gaze, std::vector<double> edges_deg)
      : display_(display), gaze_(gaze), edges_(std::move(edges_deg)) {
    for (size_t i = 1; i < edges_.size(); ++i)
      if (!(edges_[i] > edges_[i - 1])) throw std::invalid_argument("band edges must increase");
  }
  size_t count() const { return edges_.size() + 1; }
  const std::vector<double>& edges() const { return edges_; }
  size_t band_of(double eccentricity_deg) const {
    return size_t(std::upper_bound(edges_.begin(), edges_.end(), eccentricity_deg) - edges_.begin());
  }
  // f(x, y, eccentricity in degrees, band) for every pixel of a width x height image on
  // the display (its size is the display's where the tools call it), row by row.
  template <class F>
  void for_each_pixel(int width, int height, F&& f) const {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const double e = pixel_eccentricity_deg(display_, gaze_, x, y);
        f(x, y, e, band_of(e));
      }
  }

 private:
  display_geometry display_;
  gaze_point gaze_;
  std::vector<double> edges_;
};

}  // namespace fov
