// Reconstruction: every screen pixel from its k nearest traced points (thesis Sec. 4.3).
// This is the double-precision C++ path: the reference the OpenCL kernels are held to.
#pragma once

#include <cstdint>
#include <string>

#include "fov/pointset.h"
#include "fov/knn_table.h"
#include "fov/frame.h"
#include "fov/reconstruct_params.h"

namespace fov {

// RBF weights of one pixel: s(x) = sum w[i] f[i] for any values f at the k points.
// Solves [A 1; 1' 0] [w; m] = [phi(|x - x_i|); 1] with partial pivoting (A is symmetric,
// so these weights give the same s(x) as solving for the coefficients). Returns false
// when a pivot vanishes. With `condition`, also computes the system's 1-norm condition number.
bool rbf_weights(const double* px, const double* py, uint32_t k, double x, double y, double c, rbf_kernel kernel,
                 double* w, double* condition = nullptr);

// A neighbour this close to a pixel centre (pixels) is on it: the pixel takes its value,
// in every method and on both paths. The one tie rule at float precision: the C++ path
// measures distances in double, the OpenCL kernels in float, and with a point 1e-7 px away
// Shepard's weights of ~1e7 made the two differ by up to 0.08; grid points lie exactly on
// pixel centres (distance 0). The kernels get it as FOV_ON_POINT.
inline constexpr double on_point_px = 1e-4;

// Neighbours this close to the radius R, relatively (h >= R (1 - shepard_tie)), are at it: they
// weigh nothing under modified Shepard, on both paths. Neighbours tied at R in exact arithmetic
// differ there by rounding, in double on the C++ path and in float in the kernels (relative
// errors about 1e-16 and 1e-7), and when they were a pixel's only hits its depth was their
// mean on one path and one of them on the other (issue 27: 2.804 against 2.884).
inline constexpr double shepard_tie = 1e-5;

// Modified Shepard as linear weights, from a pixel's neighbours' distances h[0..k)
// (ascending, k <= max_knn): F = sum w[i] f[i], w[i] = v[i] / sum(v), v = (R - h) / (R h)
// (squared with renka), R = h[k-1], the farthest;
//  - h[i] < on_point_px (a pixel on a point): one-hot on the first such;
//  - h[i] >= R (1 - shepard_tie): v = 0 (at the radius);
//  - every v zero (all neighbours at distance R, including k = 1): 1/k each.
void shepard_weights(const double* h, uint32_t k, bool renka, double* w);

// The same rule applied to values f of any type with +, * by double and a zero default.
template <class T>
T shepard_weighted(const double* h, const T* f, uint32_t k, bool renka) {
  double w[max_knn];
  shepard_weights(h, k, renka, w);
  T acc{};
  for (uint32_t i = 0; i < k; ++i)
    if (w[i] != 0) acc = acc + f[i] * w[i];  // a neighbour without weight adds nothing, NaN included
  return acc;
}

// The weights of canvas pixel (cx, cy) under `params` (shepard, rbf, barycentric or natural):
// the pixel's value is sum w[j] f[j] over its k neighbours, nearest first, with terms of zero
// weight left out (a NaN sample there adds nothing; the OpenCL kernels follow the same rule).
// A neighbour within on_point_px of the pixel centre takes all the weight, in every method.
// Pixels a method cannot weigh take Shepard's weights instead, counted in stats by rule.
// RBF falls back where
//  - two neighbours lie closer than rbf_duplicate_fraction of their spacing (near-duplicate
//    points, which fovgen never makes but an imported set may),
//  - a pivot vanishes (a singular system), or
//  - its weights' absolute sum passes rbf_max_weight_sum: the weights sum to 1, so the value
//    can leave the neighbours' range by (sum |w| - 1) / 2 of it. This bounds what the
//    condition number only warns of: systems that pass the pivot test with condition numbers
//    of 1e17 (Gaussian kernel, shape 10, k = 32 on a grid) or whose two neighbours 2.1e-3 px
//    apart sent the value to 159x the data range (issue 27).
// Every 257th pixel or so has its condition number sampled. Barycentric and natural take the
// pixel's Delaunay weights `at` (delaunay.h, required for them) and fall back where
//  - no triangle holds the pixel (outside the points' convex hull, or all points on a line), or
//  - a point with weight is not among the pixel's k nearest (raise k: fallbacks are counted),
//    so a frame reads no point that the k-NN tables do not list, and traces none.
// Inputs are not checked (see check_reconstruct_inputs).
constexpr double rbf_duplicate_fraction = 1e-3;
constexpr double rbf_max_weight_sum = 8;
struct delaunay_weights;
void pixel_weights(const pointset& set, const reconstruct_params& params, uint32_t cx, uint32_t cy, double* w,
                   weight_stats* stats, const delaunay_weights* at = nullptr);

// Throws std::invalid_argument when the set's table is not loaded, k lies outside 1..the
// set's k, the samples belong to another set, or an RBF shape is not positive.
void check_reconstruct_inputs(const pointset& set, const point_samples& samples, const reconstruct_params& params);

// Rebuilds the screen (the set's display size) for the samples' gaze offset. Depth is
// reconstructed from the same weights over neighbours that hit something (+inf if none).
// RBF solves a system per pixel unless `cache` (built for the same params) holds its
// weights; the cache is then prepared for the samples' offset first. Barycentric and natural
// always read a cache: without one, a cache for this call is built (triangulating the set).
class weight_cache;
frame reconstruct(const pointset& set, const point_samples& samples, const reconstruct_params& params,
                  weight_stats* stats = nullptr, weight_cache* cache = nullptr);
// The same into `out` (resized to the screen when it is not), and with `only` just the pixels
// of that level of an adaptive frame's refinement map: the others keep their values.
void reconstruct_into(const pointset& set, const point_samples& samples, const reconstruct_params& params, frame& out,
                      weight_stats* stats = nullptr, weight_cache* cache = nullptr, const level_mask* only = nullptr);

}  // namespace fov
