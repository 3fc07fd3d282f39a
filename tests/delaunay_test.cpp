// Barycentric and natural-neighbour reconstruction (issue 27): the Delaunay weights, their
// rules at the hull, on points, for collinear and coincident points, and through reconstruct.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "fov/dart_throwing.h"
#include "fov/delaunay.h"
#include "fov/knn_table.h"
#include "fov/reconstruct.h"
#include "fov/weight_cache.h"
#include "test_samples.h"
#include "test_sets.h"

namespace fov {
namespace {

constexpr method delaunay_methods[] = {method::barycentric, method::natural};

// A set of the given points on a w x h screen's canvas with its table of k neighbours.
pointset set_of(std::vector<point> points, int w, int h, uint32_t k) {
  pointset set;
  set.model.display = {w, h, 1.0};
  set.points = std::move(points);
  knn_params kp;
  kp.k = k;
  set.table = build_knn_table(set.points, 2 * w, 2 * h, kp);
  return set;
}

// Darts on a small screen (as interp_test's fixture) with a linear field at every point.
struct linear_fixture {
  pointset set;
  point_samples samples;
  static glm::dvec3 field(double x, double y) { return {0.2 + 0.01 * x, 0.9 - 0.004 * y, 0.1 + 0.003 * x + 0.005 * y}; }
  linear_fixture(int w, int h, uint32_t k) {
    set = set_of(throw_darts(testing::small_model(w, h), testing::quick_darts()), w, h, k);
    samples.offset = offset_for_gaze(set.model.display, {w / 2.0, h / 2.0});
    for (const point& p : set.points) samples.colour.push_back(glm::vec3(field(p.x, p.y))), samples.depth.push_back(2.0f);
  }
};

reconstruct_params params_of(method m, uint32_t k) {
  reconstruct_params rp;
  rp.how = m;
  rp.k = k;
  return rp;
}

// Both reproduce a linear field at every pixel inside the points' hull, with k = 32 (so no
// point with weight lies beyond the k nearest: no fallback at all, on the whole canvas);
// the error left is the colours' float rounding.
TEST(Delaunay, BothReproduceALinearFieldWithoutFallbacks) {
  linear_fixture fx(64, 48, 32);
  for (method m : delaunay_methods) {
    reconstruct_params rp = params_of(m, 32);
    weight_cache cache(fx.set, rp);
    weight_stats stats;
    const frame f = reconstruct(fx.set, fx.samples, rp, &stats, &cache);
    EXPECT_EQ(stats.fallbacks, 0u) << method_name(m);
    EXPECT_EQ(stats.pixels, 128u * 96u) << method_name(m);  // the cache's tiles hold the whole canvas here
    double worst = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x) {
        const glm::dvec3 want = linear_fixture::field(x + fx.samples.offset.x + 0.5, y + fx.samples.offset.y + 0.5);
        for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::fabs(f.rgb[size_t(y) * 64 + x][ch] - want[ch]));
      }
    EXPECT_LT(worst, 2e-6) << method_name(m);
    // Shepard on the same field is no linear interpolant: the test can tell.
    rp.how = method::shepard;
    rp.k = 5;
    const frame s = reconstruct(fx.set, fx.samples, rp);
    double shepard_worst = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x) {
        const glm::dvec3 want = linear_fixture::field(x + fx.samples.offset.x + 0.5, y + fx.samples.offset.y + 0.5);
        for (int ch = 0; ch < 3; ++ch) shepard_worst = std::max(shepard_worst, std::fabs(s.rgb[size_t(y) * 64 + x][ch] - want[ch]));
      }
    EXPECT_GT(shepard_worst, 1e-3);
  }
}

// The weights at a point are that point's alone, for both methods, and sum to 1 elsewhere.
TEST(Delaunay, APointsPositionGetsItsValueAndWeightsSumToOne) {
  const std::vector<point> pts = throw_darts(testing::small_model(40, 30), testing::quick_darts());
  const delaunay t(pts);
  EXPECT_EQ(t.dimension(), 2);
  EXPECT_EQ(t.vertices(), pts.size());
  for (method m : delaunay_methods) {
    for (uint32_t i = 0; i < pts.size(); ++i) {
      const double x = pts[i].x, y = pts[i].y;
      delaunay_weights w;
      t.weigh(m, &x, &y, 1, &w);
      ASSERT_EQ(w.where, delaunay_case::inside);
      ASSERT_EQ(w.n, 1u) << method_name(m) << " point " << i;
      EXPECT_EQ(w.index[0], i);
      EXPECT_EQ(w.weight[0], 1.0);
    }
    std::mt19937 random(2);
    std::uniform_real_distribution<double> u(20, 60);
    for (int n = 0; n < 200; ++n) {
      const double x = u(random), y = u(random) * 0.75;
      delaunay_weights w;
      t.weigh(m, &x, &y, 1, &w);
      ASSERT_EQ(w.where, delaunay_case::inside);
      double sum = 0, cx = 0, cy = 0;
      for (uint32_t j = 0; j < w.n; ++j) {
        EXPECT_GE(w.weight[j], 0.0);
        sum += w.weight[j], cx += w.weight[j] * pts[w.index[j]].x, cy += w.weight[j] * pts[w.index[j]].y;
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      EXPECT_NEAR(cx, x, 1e-9);  // linear precision: the weights reproduce the position itself
      EXPECT_NEAR(cy, y, 1e-9);
      if (m == method::barycentric) {
        EXPECT_LE(w.n, 3u);
      }
    }
  }
}

// Natural-neighbour interpolation is continuous: along a line crossing many Voronoi edges in
// steps of 1e-3 px, no step changes the value by more than 1 % of the data's range, where
// nearest-neighbour jumps by far more on the same data (so the test can fail).
TEST(Delaunay, NaturalIsContinuousWhereNearestNeighbourJumps) {
  const std::vector<point> pts = throw_darts(testing::small_model(40, 30), testing::quick_darts());
  const delaunay t(pts);
  std::mt19937 random(9);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> f(pts.size());
  for (double& v : f) v = u(random);
  const size_t steps = 20000;
  std::vector<double> xs(steps), ys(steps, 31.3);
  for (size_t i = 0; i < steps; ++i) xs[i] = 25 + i * 1e-3;
  for (method m : delaunay_methods) {
    std::vector<delaunay_weights> w(steps);
    t.weigh(m, xs.data(), ys.data(), steps, w.data());
    double previous = 0, worst = 0, nn_previous = 0, nn_worst = 0;
    for (size_t i = 0; i < steps; ++i) {
      ASSERT_EQ(w[i].where, delaunay_case::inside);
      double v = 0;
      uint32_t nearest = 0;
      for (uint32_t j = 0; j < w[i].n; ++j) v += w[i].weight[j] * f[w[i].index[j]];
      for (uint32_t j = 1; j < pts.size(); ++j)
        if (std::hypot(pts[j].x - xs[i], pts[j].y - ys[i]) < std::hypot(pts[nearest].x - xs[i], pts[nearest].y - ys[i]))
          nearest = j;
      if (i > 0) worst = std::max(worst, std::fabs(v - previous)), nn_worst = std::max(nn_worst, std::fabs(f[nearest] - nn_previous));
      previous = v, nn_previous = f[nearest];
    }
    EXPECT_LT(worst, 0.01) << method_name(m);
    EXPECT_GT(nn_worst, 0.1);
  }
}

// Outside the points' convex hull, and for points all on one line (no triangle at all), a
// pixel takes Shepard's weights, counted as outside_hull.
TEST(Delaunay, OutsideTheHullAndCollinearPointsFallBackToShepard) {
  std::vector<point> line;
  for (int i = 0; i < 20; ++i) line.push_back({float(3.25 + 2.5 * i), 17.5f, 2.5f});
  const pointset set = set_of(line, 32, 24, 8);
  const delaunay t(set.points);
  EXPECT_LT(t.dimension(), 2);
  point_samples s = testing::random_samples(set.points.size(), 4);
  s.offset = offset_for_gaze(set.model.display, {16, 12});
  reconstruct_params shepard;
  shepard.k = 8;
  const frame want = reconstruct(set, s, shepard);
  for (method m : delaunay_methods) {
    reconstruct_params rp = shepard;
    rp.how = m;
    weight_stats stats;
    const frame got = reconstruct(set, s, rp, &stats);
    EXPECT_EQ(stats.outside_hull, 64u * 48u) << method_name(m);  // the whole canvas (one tile); no pixel centre lies on a point
    EXPECT_EQ(stats.fallbacks, stats.outside_hull);
    for (size_t i = 0; i < want.rgb.size(); ++i)
      for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(got.rgb[i][ch], want.rgb[i][ch], 1e-6) << method_name(m) << " pixel " << i;
  }
  // A triangle's outside: weigh says so.
  const delaunay tri({{0, 0, 1}, {10, 0, 1}, {0, 10, 1}});
  const double x = 8, y = 8;
  for (method m : delaunay_methods) {
    delaunay_weights w;
    tri.weigh(m, &x, &y, 1, &w);
    EXPECT_EQ(w.where, delaunay_case::outside) << method_name(m);
  }
}

// Of coincident points only the smallest index weighs; the frame is the frame without the
// later copies.
TEST(Delaunay, CoincidentPointsWeighOnceAtTheSmallestIndex) {
  std::vector<point> pts = throw_darts(testing::small_model(32, 24), testing::quick_darts());
  const size_t n = pts.size();
  for (size_t i = 0; i < n; i += 7) pts.push_back(pts[i]);  // copies after the originals
  const delaunay t(pts);
  EXPECT_EQ(t.vertices(), n);
  std::mt19937 random(1);
  std::uniform_real_distribution<double> u(10, 50);
  for (method m : delaunay_methods)
    for (int i = 0; i < 500; ++i) {
      const double x = u(random), y = u(random);
      delaunay_weights w;
      t.weigh(m, &x, &y, 1, &w);
      for (uint32_t j = 0; j < w.n; ++j) ASSERT_LT(w.index[j], n) << method_name(m);
    }
}

// With k too small to list a triangle's corners a pixel falls back to Shepard, counted as
// beyond_k (at k = 1 every pixel not on a point does, and the frame is nearest-neighbour's).
TEST(Delaunay, PointsBeyondTheKNearestFallBackAndAreCounted) {
  linear_fixture fx(48, 40, 20);
  for (method m : delaunay_methods) {
    reconstruct_params rp = params_of(m, 1);
    weight_stats stats;
    const frame one = reconstruct(fx.set, fx.samples, rp, &stats);
    EXPECT_EQ(stats.beyond_k + stats.outside_hull, stats.fallbacks);
    EXPECT_GT(stats.beyond_k, 48u * 40u * 9 / 10) << method_name(m);
    rp.how = method::nn;
    EXPECT_EQ(one.rgb, reconstruct(fx.set, fx.samples, rp).rgb) << method_name(m);
    rp.how = m;
    rp.k = 5;
    weight_stats five;
    reconstruct(fx.set, fx.samples, rp, &five);
    rp.k = 20;
    weight_stats twenty;
    reconstruct(fx.set, fx.samples, rp, &twenty);
    EXPECT_LT(twenty.beyond_k, five.beyond_k) << method_name(m);
    EXPECT_LT(five.beyond_k, stats.beyond_k) << method_name(m);
    EXPECT_NE(weight_fallback_warning(five, m).find(method_name(m)), std::string::npos);
  }
}

// The cache: its frame is the frame of a cache made for the call; it serves its method only.
TEST(Delaunay, TheCacheServesItsMethodAndKOnly) {
  linear_fixture fx(48, 40, 20);
  reconstruct_params rp;
  rp.how = method::natural;
  rp.k = 12;
  weight_cache cache(fx.set, rp);
  EXPECT_GT(cache.triangulation_bytes(), fx.set.points.size() * 16);
  EXPECT_EQ(reconstruct(fx.set, fx.samples, rp, nullptr, &cache).rgb, reconstruct(fx.set, fx.samples, rp).rgb);
  EXPECT_TRUE(cache.prepare(fx.samples.offset).empty());
  reconstruct_params other = rp;
  other.how = method::barycentric;
  EXPECT_FALSE(cache.serves(other));
  other = rp;
  other.k = 11;
  EXPECT_FALSE(cache.serves(other));
  other = rp;
  other.shape = 3;  // RBF's parameters do not matter here
  EXPECT_TRUE(cache.serves(other));
  reconstruct_params shepard;
  EXPECT_THROW(weight_cache(fx.set, shepard), std::invalid_argument);
}

}  // namespace
}  // namespace fov
