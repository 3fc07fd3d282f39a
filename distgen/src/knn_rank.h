// How the k-NN table and the k-NN cells rank points (private to distgen): by squared
// distance in double from the float coordinates, ties to the smaller index.
#pragma once

#include <cstdint>

#include "fov/pointset.h"

namespace fov::knn_rank {

struct ranked {
  double d2;
  uint32_t index;
  bool operator<(const ranked& o) const { return d2 < o.d2 || (d2 == o.d2 && index < o.index); }
};

inline double distance2(const point& p, double qx, double qy) {
  const double dx = double(p.x) - qx, dy = double(p.y) - qy;
  return dx * dx + dy * dy;
}

// FLANN searches in float: it is asked for this many more neighbours than wanted, which are
// then re-ranked in double.
inline constexpr uint32_t extra_candidates = 6;

}  // namespace fov::knn_rank
