// Samples and reconstruction cases for tests that compare two ways of reconstructing.
#pragma once

#include <cmath>
#include <random>

#include "fov/frame.h"
#include "fov/reconstruct_params.h"

namespace fov::testing {

// Random colours at n points, every fifth point a miss (infinite depth).
inline point_samples random_samples(size_t n, unsigned seed) {
  point_samples s;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> u(0, 1);
  for (size_t i = 0; i < n; ++i)
    s.colour.push_back({u(random), u(random), u(random)}), s.depth.push_back(i % 5 ? 1 + u(random) : INFINITY);
  return s;
}

// Calls f(params) for nn, Shepard (Renka's weights every fourth case), RBF, barycentric and
// natural at k = 1, 5 and 20, at each gaze, with s placed there and mirrored in turn.
template <class F>
void for_each_reconstruction(const display_geometry& display, std::initializer_list<gaze_point> gazes, point_samples& s,
                             F&& f) {
  int round = 0;
  for (gaze_point gaze : gazes)
    for (method m : {method::nn, method::shepard, method::rbf, method::barycentric, method::natural})
      for (uint32_t k : {1u, 5u, 20u}) {
        if (m == method::nn && k != 1) continue;
        s.offset = offset_for_gaze(display, gaze);
        s.mirror_x = ++round % 2 == 0, s.mirror_y = round % 3 == 0;
        reconstruct_params rp;
        rp.how = m;
        rp.k = k;
        rp.renka = m == method::shepard && round % 4 == 0;
        f(rp);
      }
}

}  // namespace fov::testing
