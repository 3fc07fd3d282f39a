// Reconstruction: every screen pixel from its k nearest traced points (thesis Sec. 4.3).
// This is the double-precision C++ path: the reference the OpenCL kernels are held to.
#pragma once

#include <cstdint>
#include <string>

#include "fov/pointset.h"
#include "fov/trace.h"

namespace fov {

enum class method : uint8_t {
  nn,       // colour of the nearest point
  shepard,  // modified Shepard (thesis Eqs. 5-6)
};
const char* method_name(method m);
bool parse_method(const std::string& name, method& out);

struct reconstruct_params {
  method how = method::shepard;
  uint32_t k = 5;       // neighbours read, 1..the set's k
  bool renka = false;   // Shepard: Renka's squared weights ((R - h) / (R h))^2
};

// Modified Shepard for one pixel from its neighbours' distances h[0..k) (ascending) and
// values f: F = sum(w f) / sum(w), w = (R - h) / (R h), R = h[k-1], the farthest.
//  - h[i] == 0 (a pixel exactly on a point): that point's value;
//  - every weight zero (all neighbours at distance R, including k = 1): the mean of f.
// Written for any value type with +, * by double and a zero default value.
template <class T>
T shepard_weighted(const double* h, const T* f, uint32_t k, bool renka) {
  const double r = h[k - 1];
  double wsum = 0;
  T acc{};
  for (uint32_t i = 0; i < k; ++i) {
    if (h[i] == 0) return f[i];
    double w = (r - h[i]) / (r * h[i]);
    if (renka) w *= w;
    acc = acc + f[i] * w;
    wsum += w;
  }
  if (wsum > 0) return acc * (1.0 / wsum);
  T mean{};
  for (uint32_t i = 0; i < k; ++i) mean = mean + f[i];
  return mean * (1.0 / k);
}

// Rebuilds the screen (the set's display size) for the samples' gaze offset. Depth is
// reconstructed from the same weights over neighbours that hit something (+inf if none).
frame reconstruct(const pointset& set, const point_samples& samples, const reconstruct_params& params);

}  // namespace fov
