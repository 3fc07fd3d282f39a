// The Delaunay triangulation of a set's points and the two interpolations it defines
// (issue 27, docs/reconstruction.md): barycentric (linear over the triangle that holds a
// position, HVVR's reconstruction) and Sibson's natural-neighbour coordinates. Both weights
// depend on the points' positions only, so weight_cache keeps them per canvas pixel as it
// keeps RBF's. CGAL computes both (exact predicates, inexact constructions); its headers stay
// in delaunay.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "fov/knn_table.h"
#include "fov/pointset.h"
#include "fov/reconstruct_params.h"

namespace fov {

// What the weights at one position are.
enum class delaunay_case : uint8_t {
  inside,   // weights over the points of the triangle (barycentric) or the natural neighbours
  outside,  // outside the points' convex hull, or every point on one line (no triangle at all)
  crowded,  // more natural neighbours than max_knn (never met in fovgen's sets)
};

struct delaunay_weights {
  delaunay_case where = delaunay_case::outside;
  uint32_t n = 0;  // contributing points: index[0..n), weights summing to 1
  uint32_t index[max_knn];
  double weight[max_knn];
};

class delaunay {
 public:
  // Triangulates `points`. Of points at one position only the one with the smallest index
  // takes part (the others weigh nothing, everywhere). Cost: O(n log n) time, memory linear
  // in the points (bytes()).
  explicit delaunay(const std::vector<point>& points);
  ~delaunay();
  delaunay(const delaunay&) = delete;
  delaunay& operator=(const delaunay&) = delete;

  // The weights of method `how` (barycentric or natural) at (x[i], y[i]), i < count. Each
  // position's walk starts where the previous one ended: pass a row of pixels, not a shuffle.
  // Weights below delaunay_weight_floor of their sum are dropped and the rest renormalised;
  // on a triangle's edge barycentric weighs the edge's two points, on a point that point.
  // Safe to call from several threads at once.
  void weigh(method how, const double* x, const double* y, size_t count, delaunay_weights* out) const;

  int dimension() const;      // 2 unless the points are fewer than 3 or all on a line
  size_t vertices() const;    // distinct positions triangulated
  size_t faces() const;       // finite triangles
  size_t bytes() const;       // memory held, estimated from the vertex and face counts
  double seconds() const;     // time the triangulation took

 private:
  struct impl;
  std::unique_ptr<impl> impl_;
};

inline constexpr double delaunay_weight_floor = 1e-9;

}  // namespace fov
