// What a reconstruction is asked for: the method, its neighbours and its parameters.
// Shared by the C++ path, the OpenCL kernels' host side and the RBF weight cache.
#pragma once

#include <cstdint>
#include <string>

#include "fov/labels.h"

namespace fov {

enum class method : uint8_t {
  nn,       // colour of the nearest point
  shepard,  // modified Shepard (thesis Eqs. 5-6)
  rbf,      // radial basis functions with a constant term (thesis Eqs. 7-10, augmented)
  barycentric,  // linear over the Delaunay triangle that holds the pixel (HVVR; delaunay.h)
  natural,      // Sibson's natural-neighbour coordinates over the Delaunay triangulation
};

enum class rbf_kernel : uint8_t {
  multiquadric,  // phi(r) = sqrt(r^2 + c^2)
  gaussian,      // phi(r) = exp(-(r / c)^2)
};
// The label tables: names for the command lines, JSON and CSV files.
inline constexpr std::pair<const char*, method> method_labels[] = {
    {"nn", method::nn},
    {"shepard", method::shepard},
    {"rbf", method::rbf},
    {"barycentric", method::barycentric},
    {"natural", method::natural}};
inline constexpr std::pair<const char*, rbf_kernel> rbf_kernel_labels[] = {
    {"multiquadric", rbf_kernel::multiquadric}, {"gaussian", rbf_kernel::gaussian}};
inline const char* method_name(method m) { return label_of(method_labels, m); }
// Methods whose weights depend on the points' positions only: weight_cache keeps them per
// canvas pixel and the kernels apply them as a weighted sum (reconstruct_weighted).
inline bool cached_weights_method(method m) { return m == method::rbf || m == method::barycentric || m == method::natural; }
inline bool delaunay_method(method m) { return m == method::barycentric || m == method::natural; }

struct reconstruct_params {
  method how = method::shepard;
  uint32_t k = 5;       // neighbours read, 1..the set's k
  bool renka = false;   // Shepard: Renka's squared weights ((R - h) / (R h))^2
  rbf_kernel kernel = rbf_kernel::multiquadric;
  double shape = 1.0;   // RBF: c = shape x the mean spacing p of the pixel's k neighbours
};

// What a reconstruction from cached weights met: pixels that fell back to Shepard's weights,
// by rule (reconstruct.h, pixel_weights), and for RBF the worst 1-norm condition number among
// sampled pixels and the largest sum of |weights| among the systems kept.
struct weight_stats {
  uint64_t pixels = 0, fallbacks = 0, sampled = 0;
  uint64_t near_duplicates = 0;  // RBF fallbacks: two neighbours closer than rbf_duplicate_fraction
  uint64_t singular = 0;         // RBF fallbacks: a pivot vanished
  uint64_t weight_sum = 0;       // RBF fallbacks: the weights' |sum| passed rbf_max_weight_sum
  uint64_t outside_hull = 0;     // Delaunay fallbacks: no triangle holds the pixel
  uint64_t beyond_k = 0;         // Delaunay fallbacks: a point with weight is not among the k neighbours
  double worst_condition = 0;
  double worst_weight_sum = 0;
  weight_stats& operator+=(const weight_stats& o);
};
// One line for stderr when some pixels fell back (how many, by which rule), else "".
std::string weight_fallback_warning(const weight_stats& s, method how);

// Throws std::invalid_argument unless k lies in 1..k_stored and an RBF shape is positive
// and finite; returns quietly otherwise.
void check_reconstruct_params(const reconstruct_params& params, uint32_t k_stored);

}  // namespace fov
