#include <cmath>
#include <limits>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "fov/dart_throwing.h"
#include "fov/knn_cells.h"
#include "fov/knn_table.h"
#include "fov/weight_cache.h"
#include "fov/reconstruct.h"
#include "test_samples.h"
#include "test_sets.h"

namespace fov {
namespace {

// A small set with its table, and samples whose colours come from f(x, y) at each point.
struct fixture {
  pointset set;
  point_samples samples;
  template <class F>
  fixture(int w, int h, gaze_point gaze, F f) {
    set.model.display = {w, h, 1.0};
    set.points = throw_darts(set.model, {});
    knn_params kp;
    kp.k = 32;
    set.table = build_knn_table(set.points, 2 * w, 2 * h, kp);
    samples.offset = offset_for_gaze(set.model.display, gaze);
    samples.colour.resize(set.points.size());
    samples.depth.assign(set.points.size(), 2.0f);
    for (size_t i = 0; i < set.points.size(); ++i) samples.colour[i] = f(set.points[i].x, set.points[i].y);
  }
};

// Issue 15: a smooth field stays smooth where the foveal grid meets the darts. Every method
// returns the field exactly on grid pixels; in the ring where grid and darts mix, the mean
// error is no larger than among the darts just outside, and no pixel there jumps.
TEST(FovealGrid, ASmoothFieldStaysSmoothAcrossTheSeam) {
  knn_params kp;
  kp.k = 8;
  const pointset set = generate_pointset(testing::partial_grid_model(), testing::grid_darts(), kp);
  const int w = set.model.display.width, h = set.model.display.height;
  auto field = [](double x, double y) { return 0.5 + 0.4 * std::sin(x / 9.0) * std::cos(y / 11.0); };
  point_samples samples;
  samples.offset = offset_for_gaze(set.model.display, screen_centre(set.model.display));
  samples.colour.resize(set.points.size());
  samples.depth.assign(set.points.size(), 1.0f);
  for (size_t i = 0; i < set.points.size(); ++i)
    samples.colour[i] = glm::vec3(float(field(set.points[i].x, set.points[i].y)));
  // The rim: the grid's radius along the row through the centre.
  double rim = 0;
  for (int x = w; x < 2 * w; ++x)
    if (!is_grid_pixel(set.model, set.darts, uint32_t(x), uint32_t(h))) {
      rim = x + 0.5 - w;
      break;
    }
  ASSERT_GT(rim, 20.0);
  for (method m : {method::nn, method::shepard, method::rbf}) {
    reconstruct_params rp;
    rp.how = m;
    rp.k = 5;
    const frame f = reconstruct(set, samples, rp);
    double seam_sum = 0, outside_sum = 0, seam_worst = 0, outside_worst = 0;
    size_t seam_n = 0, outside_n = 0, grid_exact = 0, grid_n = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double cx = x + samples.offset.x + 0.5, cy = y + samples.offset.y + 0.5;
        const double d = std::hypot(cx - w, cy - h);
        const double err = std::fabs(f.rgb[size_t(y) * w + x].r - field(cx, cy));
        if (is_grid_pixel(set.model, set.darts, uint32_t(cx), uint32_t(cy))) {
          ++grid_n;
          grid_exact += f.rgb[size_t(y) * w + x].r == float(field(cx, cy));
        }
        if (std::fabs(d - rim) < 3) seam_sum += err, ++seam_n, seam_worst = std::max(seam_worst, err);
        if (d >= rim + 3 && d < rim + 9) outside_sum += err, ++outside_n, outside_worst = std::max(outside_worst, err);
      }
    ASSERT_GT(seam_n, 100u);
    ASSERT_GT(outside_n, 100u);
    EXPECT_EQ(grid_exact, grid_n) << method_name(m);
    EXPECT_LE(seam_sum / seam_n, outside_sum / outside_n) << method_name(m);
    // A single pixel at the rim may sit a little farther from its nearest point than any
    // among the darts outside (darts keep their spacing from the grid); a gap would double it.
    EXPECT_LE(seam_worst, 1.5 * outside_worst) << method_name(m);
  }
}

TEST(Shepard, PixelOnAPointReturnsItsValue) {
  const double h[3] = {0.0, 1.0, 2.0};
  const double f[3] = {7.0, 1.0, 2.0};
  EXPECT_EQ(shepard_weighted(h, f, 3, false), 7.0);
  const double h2[3] = {0.5, 0.0, 2.0};  // not first in the list: still exact
  EXPECT_EQ(shepard_weighted(h2, f, 3, true), 1.0);
}

TEST(Shepard, EquidistantNeighboursGiveTheirMean) {
  // All weights (R - h) / (R h) are zero: the documented result is the plain mean.
  const double h[4] = {2.0, 2.0, 2.0, 2.0};
  const double f[4] = {1.0, 2.0, 3.0, 6.0};
  EXPECT_DOUBLE_EQ(shepard_weighted(h, f, 4, false), 3.0);
  const double one_h[1] = {0.7}, one_f[1] = {5.0};
  EXPECT_DOUBLE_EQ(shepard_weighted(one_h, one_f, 1, false), 5.0);  // k = 1 is nearest neighbour
}

TEST(Shepard, WeightsFollowEquationSix) {
  // h = 1, 2, 4 (R = 4): w = 3/4, 2/8 = 1/4, 0 -> F = (0.75 * 10 + 0.25 * 20) / 1 = 12.5.
  const double h[3] = {1, 2, 4};
  const double f[3] = {10, 20, 1000};
  EXPECT_DOUBLE_EQ(shepard_weighted(h, f, 3, false), 12.5);
  // Renka: w^2 = 9/16, 1/16 -> (9 * 10 + 1 * 20) / 10 = 11.
  EXPECT_DOUBLE_EQ(shepard_weighted(h, f, 3, true), 11.0);
}

TEST(Reconstruct, EveryMethodReproducesAConstantFieldAtEveryK) {
  const glm::vec3 c(0.25f, 0.5f, 0.75f);
  fixture fx(48, 40, {20, 25}, [&](float, float) { return c; });
  for (method m : {method::nn, method::shepard})
    for (uint32_t k : {1u, 2u, 5u, 10u, 20u, 32u})
      for (bool renka : {false, true}) {
        reconstruct_params rp;
        rp.how = m;
        rp.k = k;
        rp.renka = renka;
        const frame f = reconstruct(fx.set, fx.samples, rp);
        ASSERT_EQ(f.rgb.size(), 48u * 40u);
        for (size_t i = 0; i < f.rgb.size(); ++i)
          for (int ch = 0; ch < 3; ++ch)
            ASSERT_NEAR(f.rgb[i][ch], c[ch], 1e-5 * c[ch]) << method_name(m) << " k=" << k << " pixel " << i;
        EXPECT_FLOAT_EQ(f.depth[100], 2.0f);
      }
}

// Issue 24: a set that keeps its neighbours as cells (storage that grows with the points)
// rebuilds the same frame as the same set with the exact table, bit for bit: every method,
// every k, mirrored patterns, RBF solved per pixel and from its weight cache, on dart sets
// (one seen from afar, whose cells grow to 4 pixels and more) and on a grid fovea (exact ties).
TEST(Cells, EveryMethodGivesTheTablesFrameBitForBit) {
  for (int kind : {0, 1, 2}) {
    const bool grid = kind == 1;
    const spacing_model m = kind == 0 ? testing::small_model(48, 40)
                            : grid    ? testing::partial_grid_model()
                                      : testing::small_model(256, 192, 10.0, 4.0);
    const testing::table_and_cells both = testing::both_ways(m, grid ? testing::grid_darts() : testing::quick_darts(), 20);
    const pointset &with_table = both.table, &with_cells = both.cells;
    ASSERT_EQ(stored_k(with_cells), 20u);
    uint32_t widest = 0;
    for (uint32_t t : with_cells.cells.tiles) widest = std::max(widest, t & 7u);
    if (kind == 2) {
      EXPECT_GE(widest, 2u);  // cells of 4 pixels and more are exercised
    }
    point_samples s = testing::random_samples(with_table.points.size(), 3);
    testing::for_each_reconstruction(m.display, {gaze_point{20, 25}, gaze_point{0, 0}, gaze_point{1e4, 1e4}}, s, [&](const reconstruct_params& rp) {
      const frame a = reconstruct(with_table, s, rp), b = reconstruct(with_cells, s, rp);
      ASSERT_EQ(a.rgb, b.rgb) << method_name(rp.how) << " k=" << rp.k << " kind " << kind;
      ASSERT_EQ(a.depth, b.depth) << method_name(rp.how) << " k=" << rp.k << " kind " << kind;
      if (cached_weights_method(rp.how)) {
        weight_cache cache(with_cells, rp);
        weight_cache table_cache(with_table, rp);
        ASSERT_EQ(reconstruct(with_cells, s, rp, nullptr, &cache).rgb, reconstruct(with_table, s, rp, nullptr, &table_cache).rgb);
      }
    });
  }
}

TEST(Reconstruct, NearestNeighbourMatchesBruteForce) {
  fixture fx(40, 32, {10, 10}, [](float x, float y) { return glm::vec3(x, y, x * y); });
  reconstruct_params rp;
  rp.how = method::nn;
  rp.k = 1;
  const frame f = reconstruct(fx.set, fx.samples, rp);
  for (int y = 0; y < 32; y += 3)
    for (int x = 0; x < 40; x += 3) {
      const float cx = float(x + fx.samples.offset.x) + 0.5f, cy = float(y + fx.samples.offset.y) + 0.5f;
      const uint32_t nearest = brute_force_knn(fx.set.points, cx, cy, 1)[0];
      ASSERT_EQ(f.rgb[size_t(y) * 40 + x], fx.samples.colour[nearest]);
    }
}

TEST(Reconstruct, ShepardMatchesADoublePrecisionReferenceOnRandomFields) {
  std::mt19937 random(3);
  std::uniform_real_distribution<float> u(0, 1);
  fixture fx(40, 32, {30, 5}, [&](float, float) { return glm::vec3(u(random), u(random), u(random)); });
  for (uint32_t k : {1u, 5u, 10u, 20u, 32u}) {
    reconstruct_params rp;
    rp.k = k;
    const frame f = reconstruct(fx.set, fx.samples, rp);
    for (int y = 0; y < 32; y += 5)
      for (int x = 0; x < 40; x += 5) {
        const double cx = x + fx.samples.offset.x + 0.5, cy = y + fx.samples.offset.y + 0.5;
        const auto nn = brute_force_knn(fx.set.points, float(cx), float(cy), k);
        double h[32], r[32];
        for (uint32_t j = 0; j < k; ++j) {
          const point& p = fx.set.points[nn[j]];
          h[j] = std::hypot(double(p.x) - cx, double(p.y) - cy);
          r[j] = fx.samples.colour[nn[j]].r;
        }
        ASSERT_NEAR(f.rgb[size_t(y) * 40 + x].r, shepard_weighted(h, r, k, false), 1e-6) << "k=" << k;
      }
  }
}

TEST(Reconstruct, RejectsKBeyondTheTable) {
  fixture fx(16, 16, {8, 8}, [](float, float) { return glm::vec3(1); });
  reconstruct_params rp;
  rp.k = 33;
  EXPECT_THROW(reconstruct(fx.set, fx.samples, rp), std::invalid_argument);
  rp.k = 0;
  EXPECT_THROW(reconstruct(fx.set, fx.samples, rp), std::invalid_argument);
  rp.k = 5;
  fx.set.table.entries.clear();  // a set loaded without its table
  EXPECT_THROW(reconstruct(fx.set, fx.samples, rp), std::invalid_argument);
}

TEST(Rbf, ReproducesAConstantFieldAtEveryKWithBothKernels) {
  const glm::vec3 c(0.25f, 0.5f, 0.75f);
  fixture fx(40, 36, {20, 18}, [&](float, float) { return c; });
  for (rbf_kernel kernel : {rbf_kernel::multiquadric, rbf_kernel::gaussian})
    for (uint32_t k : {1u, 2u, 5u, 10u, 20u, 32u}) {
      reconstruct_params rp;
      rp.how = method::rbf;
      rp.k = k;
      rp.kernel = kernel;
      weight_stats stats;
      const frame f = reconstruct(fx.set, fx.samples, rp, &stats);
      for (size_t i = 0; i < f.rgb.size(); ++i)
        for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(f.rgb[i][ch], c[ch], 1e-5 * c[ch]) << "k=" << k << " pixel " << i;
      EXPECT_EQ(stats.pixels, 40u * 36u);
      EXPECT_GT(stats.sampled, 0u);
      EXPECT_TRUE(std::isfinite(stats.worst_condition));
      EXPECT_GE(stats.worst_condition, 1.0);
    }
}

TEST(Shepard, LinearWeightsGiveTheSameValues) {
  const double h[4] = {0.5, 1.0, 2.0, 4.0}, f[4] = {3.0, -1.0, 2.0, 8.0};
  double w[4], s = 0, sum = 0;
  for (bool renka : {false, true}) {
    shepard_weights(h, 4, renka, w);
    s = sum = 0;
    for (int i = 0; i < 4; ++i) s += w[i] * f[i], sum += w[i];
    EXPECT_NEAR(s, shepard_weighted(h, f, 4, renka), 1e-12);
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
  const double on_point[3] = {1.0, 0.0, 2.0};  // one-hot on an exact hit
  shepard_weights(on_point, 3, false, w);
  EXPECT_EQ(w[0], 0.0);
  EXPECT_EQ(w[1], 1.0);
  const double equal[3] = {2.0, 2.0, 2.0};  // all weights zero: the mean
  shepard_weights(equal, 3, false, w);
  EXPECT_DOUBLE_EQ(w[2], 1.0 / 3);
}

TEST(Mirror, AMirroredPatternIsTheFlippedFrameOfTheSameSamples) {
  // The same samples read through a mirrored table give the frame flipped, for every
  // method (the weights depend on distances only, which mirroring keeps).
  std::mt19937 random(11);
  std::uniform_real_distribution<float> u(0, 1);
  fixture fx(40, 30, {13, 9}, [&](float, float) { return glm::vec3(u(random), u(random), u(random)); });
  for (method m : {method::nn, method::shepard, method::rbf}) {
    reconstruct_params rp;
    rp.how = m;
    const frame plain = reconstruct(fx.set, fx.samples, rp);
    for (int mirror = 1; mirror < 4; ++mirror) {
      point_samples s = fx.samples;
      s.mirror_x = mirror & 1, s.mirror_y = mirror & 2;
      const frame flipped = reconstruct(fx.set, s, rp);
      for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
          const int fx_ = s.mirror_x ? 39 - x : x, fy = s.mirror_y ? 29 - y : y;
          ASSERT_EQ(flipped.rgb[size_t(y) * 40 + x], plain.rgb[size_t(fy) * 40 + fx_]) << method_name(m) << " " << mirror;
        }
    }
  }
}

TEST(RbfCache, CachedWeightsGiveTheDirectSolveAndComputeEachTileOnce) {
  std::mt19937 random(3);
  std::uniform_real_distribution<float> u(0, 1);
  fixture fx(90, 70, {30, 50}, [&](float, float) { return glm::vec3(u(random), u(random), u(random)); });
  for (rbf_kernel kernel : {rbf_kernel::multiquadric, rbf_kernel::gaussian})
    for (uint32_t k : {1u, 5u, 20u, 32u}) {
      reconstruct_params rp;
      rp.how = method::rbf;
      rp.k = k;
      rp.kernel = kernel;
      weight_cache cache(fx.set, rp);
      EXPECT_EQ(cache.tiles_ready(), 0u);
      const frame cached = reconstruct(fx.set, fx.samples, rp, nullptr, &cache);
      const frame direct = reconstruct(fx.set, fx.samples, rp);
      for (size_t i = 0; i < cached.rgb.size(); ++i)
        for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(cached.rgb[i][ch], direct.rgb[i][ch], 1e-5) << "k=" << k << " pixel " << i;
      EXPECT_EQ(cached.depth, direct.depth);
      // The 90 x 70 screen at offset (60, 20) on the 180 x 140 canvas covers tiles x 0..2, y 0..1.
      EXPECT_EQ(cache.tiles_ready(), 6u);
      EXPECT_TRUE(cache.prepare(fx.samples.offset).empty());  // nothing left to compute
      point_samples moved = fx.samples;
      moved.offset = {0, 0};
      EXPECT_EQ(cache.prepare(moved.offset).size(), 0u);  // tiles x 0..1, y 0..1: all ready
      moved.offset = {90, 70};
      EXPECT_EQ(cache.prepare(moved.offset).size(), 2u);  // tiles x 1..2, y 1..2: row y = 2 is new
    }
  reconstruct_params other;
  other.how = method::rbf;
  weight_cache cache(fx.set, other);
  other.shape = 2;
  EXPECT_FALSE(cache.serves(other));
  EXPECT_THROW(reconstruct(fx.set, fx.samples, other, nullptr, &cache), std::invalid_argument);
}

TEST(Rbf, InterpolatesExactlyAtThePoints) {
  const double x[4] = {0, 1.3, 0.2, 2.0}, y[4] = {0, 0.1, 1.7, 1.1};
  double w[4];
  for (int at = 0; at < 4; ++at) {
    ASSERT_TRUE(rbf_weights(x, y, 4, x[at], y[at], 0.8, rbf_kernel::multiquadric, w));
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(w[i], i == at ? 1.0 : 0.0, 1e-9);
  }
}

// The thesis's form: solve [A 1; 1' 0] [lambda; mu] = [f; 0] and evaluate
// s(x) = sum lambda_i phi(|x - x_i|) + mu, by Gauss-Jordan elimination.
double rbf_by_coefficients(const double* x, const double* y, const double* f, int k, double px, double py, double c) {
  const int n = k + 1;
  std::vector<double> m(size_t(n) * (n + 1));
  auto at = [&](int r, int col) -> double& { return m[size_t(r) * (n + 1) + col]; };
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) at(i, j) = std::sqrt(std::pow(std::hypot(x[i] - x[j], y[i] - y[j]), 2) + c * c);
    at(i, k) = at(k, i) = 1;
    at(i, n) = f[i];
  }
  at(k, k) = 0;
  at(k, n) = 0;
  for (int col = 0; col < n; ++col) {
    int best = col;
    for (int r = col + 1; r < n; ++r)
      if (std::fabs(at(r, col)) > std::fabs(at(best, col))) best = r;
    for (int j = 0; j <= n; ++j) std::swap(at(col, j), at(best, j));
    for (int r = 0; r < n; ++r) {
      if (r == col) continue;
      const double g = at(r, col) / at(col, col);
      for (int j = col; j <= n; ++j) at(r, j) -= g * at(col, j);
    }
  }
  double s = at(k, n) / at(k, k);
  for (int i = 0; i < k; ++i) s += at(i, n) / at(i, i) * std::sqrt(std::pow(std::hypot(px - x[i], py - y[i]), 2) + c * c);
  return s;
}

TEST(Rbf, WeightsAgreeWithSolvingForCoefficients) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> u(0, 4);
  for (int k : {1, 3, 5, 10, 20, 32}) {
    std::vector<double> x(k), y(k), f(k), w(k);
    for (int i = 0; i < k; ++i) x[i] = u(random), y[i] = u(random), f[i] = u(random);
    const double px = u(random), py = u(random);
    ASSERT_TRUE(rbf_weights(x.data(), y.data(), uint32_t(k), px, py, 1.1, rbf_kernel::multiquadric, w.data()));
    double s = 0;
    for (int i = 0; i < k; ++i) s += w[i] * f[i];
    EXPECT_NEAR(s, rbf_by_coefficients(x.data(), y.data(), f.data(), k, px, py, 1.1), 1e-7) << "k=" << k;
  }
}

TEST(Rbf, DuplicatePointsFallBackToShepard) {
  const double x[3] = {1, 1, 2}, y[3] = {1, 1, 0};
  double w[3];
  EXPECT_FALSE(rbf_weights(x, y, 3, 0.5, 0.5, 1.0, rbf_kernel::multiquadric, w));
}

// Points all but on top of each other (an imported set; 1e-7 px apart) pass the pivot test
// with condition numbers of 1e14 and more (issue 16 measured a constant field off by up to
// 0.37 through the float weight cache). Such pixels now fall back to Shepard, counted, and
// the constant comes back from the solve and the cache alike.
TEST(Rbf, NearDuplicateNeighboursFallBackAndKeepAConstantField) {
  const glm::vec3 c(0.25f, 0.5f, 0.75f);
  fixture fx(48, 40, {24, 20}, [&](float, float) { return c; });
  knn_table& t = fx.set.table;
  uint32_t moved = 0;
  for (uint32_t y = 8; y < t.height; y += 16)  // a pixel's second neighbour moved onto its first
    for (uint32_t x = 8; x < t.width; x += 16, ++moved) {
      const point& a = fx.set.points[t.at(x, y, 0)];
      point& b = fx.set.points[t.at(x, y, 1)];
      b.x = a.x + 1e-7f * std::max(1.0f, a.x), b.y = a.y;
    }
  ASSERT_GT(moved, 10u);
  for (uint32_t k : {5u, 20u}) {
    reconstruct_params rp;
    rp.how = method::rbf;
    rp.k = k;
    weight_stats stats;
    weight_cache cache(fx.set, rp);
    const frame direct = reconstruct(fx.set, fx.samples, rp, &stats);
    const frame cached = reconstruct(fx.set, fx.samples, rp, nullptr, &cache);
    EXPECT_GT(stats.fallbacks, 0u) << "k=" << k;
    for (size_t i = 0; i < direct.rgb.size(); ++i)
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_NEAR(direct.rgb[i][ch], c[ch], 1e-5) << "k=" << k << " pixel " << i;
        ASSERT_NEAR(cached.rgb[i][ch], c[ch], 1e-5) << "k=" << k << " pixel " << i;
      }
  }
}

// Past rbf_max_weight_sum a pixel's RBF weights fall back to Shepard (issue 27): two
// neighbours 2.1e-3 spacings apart (just past the near-duplicate rule) at k = 2, and a
// Gaussian kernel at shape 10 with k = 32 on a grid set. No pixel then leaves the data's range
// by more than (rbf_max_weight_sum - 1) / 2 of it, on the direct solve and the cache alike,
// and the rule is counted apart from the others.
TEST(Rbf, WeightsWhoseAbsoluteSumPassesTheBoundFallBack) {
  std::mt19937 random(5);
  std::uniform_real_distribution<float> u(0, 1);
  const double slack = (rbf_max_weight_sum - 1) / 2;
  auto bounded = [&](const frame& f, const std::string& what) {
    for (size_t i = 0; i < f.rgb.size(); ++i)
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_GE(f.rgb[i][ch], -slack - 1e-5) << what << " pixel " << i;
        ASSERT_LE(f.rgb[i][ch], 1 + slack + 1e-5) << what << " pixel " << i;
      }
  };
  {  // near-duplicate pairs, k = 2
    fixture fx(48, 40, {24, 20}, [&](float, float) { return glm::vec3(u(random), u(random), u(random)); });
    knn_table& t = fx.set.table;
    double largest = 0;
    for (uint32_t y = 8; y < t.height; y += 16)
      for (uint32_t x = 8; x < t.width; x += 16) {
        const point& a = fx.set.points[t.at(x, y, 0)];
        point& b = fx.set.points[t.at(x, y, 1)];
        const float apart = 2.1e-3f * std::max(a.spacing, b.spacing);
        b.x = a.x + apart, b.y = a.y;
        // What the solve alone gives the pixel: weights far past the bound.
        const double xs[2] = {a.x, b.x}, ys[2] = {a.y, b.y};
        double w[2];
        const double spacing = (a.spacing + b.spacing) / 2;
        if (rbf_weights(xs, ys, 2, x + 0.5, y + 0.5, spacing / 2, rbf_kernel::multiquadric, w))
          largest = std::max(largest, std::fabs(w[0]) + std::fabs(w[1]));
      }
    EXPECT_GT(largest, 10 * rbf_max_weight_sum) << "the stress is not one";
    reconstruct_params rp;
    rp.how = method::rbf;
    rp.k = 2;
    weight_stats stats;
    weight_cache cache(fx.set, rp);
    bounded(reconstruct(fx.set, fx.samples, rp, &stats), "k = 2, direct");
    bounded(reconstruct(fx.set, fx.samples, rp, nullptr, &cache), "k = 2, cached");
    EXPECT_GT(stats.weight_sum, 0u);
    EXPECT_EQ(stats.fallbacks, stats.weight_sum + stats.near_duplicates + stats.singular);
    EXPECT_LE(stats.worst_weight_sum, rbf_max_weight_sum);
    EXPECT_NE(weight_fallback_warning(stats, method::rbf).find(std::to_string(stats.fallbacks) + " of"), std::string::npos)
        << weight_fallback_warning(stats, method::rbf);
  }
  {  // Gaussian, shape 10, k = 32, on a grid set
    knn_params kp;
    kp.k = 32;
    pointset set = generate_pointset(testing::partial_grid_model(), testing::grid_darts(), kp);
    point_samples s;
    s.offset = offset_for_gaze(set.model.display, {64, 48});
    s.colour.resize(set.points.size());
    s.depth.assign(set.points.size(), 2.0f);
    for (glm::vec3& c : s.colour) c = {u(random), u(random), u(random)};
    reconstruct_params rp;
    rp.how = method::rbf;
    rp.k = 32;
    rp.kernel = rbf_kernel::gaussian;
    rp.shape = 10;
    weight_stats stats;
    bounded(reconstruct(set, s, rp, &stats), "gaussian k = 32");
    EXPECT_GT(stats.weight_sum + stats.singular, 0u);
    EXPECT_LE(stats.worst_weight_sum, rbf_max_weight_sum);
  }
  EXPECT_EQ(weight_fallback_warning({}, method::rbf), "");
}

// Neighbours at the radius within shepard_tie weigh nothing (issue 27): two neighbours tied at
// R but for rounding give their mean, not the nearer one's value.
TEST(Shepard, NeighboursAtTheRadiusWithinTheTieWeighNothing) {
  double w[3];
  const double near_tie[3] = {0.5, 1.0 - 1e-9, 1.0};
  shepard_weights(near_tie, 3, false, w);
  EXPECT_EQ(w[0], 1.0);
  EXPECT_EQ(w[1], 0.0);
  const double tied[2] = {1.0 - 1e-9, 1.0};
  shepard_weights(tied, 2, false, w);
  EXPECT_EQ(w[0], 0.5);
  EXPECT_EQ(w[1], 0.5);
  const double apart[2] = {1.0 - 1e-4, 1.0};  // beyond the tie: the nearer takes all
  shepard_weights(apart, 2, false, w);
  EXPECT_EQ(w[0], 1.0);
}

// A neighbour whose weight is zero adds nothing, NaN included (the k-th neighbour under
// modified Shepard always weighs zero): the pixel keeps its value; the OpenCL kernels follow
// the same rule (cl_reconstruct_test).
TEST(Reconstruct, ANaNSampleWithoutWeightChangesNothing) {
  const glm::vec3 c(0.25f, 0.5f, 0.75f);
  fixture fx(40, 36, {20, 18}, [&](float, float) { return c; });
  const knn_table& t = fx.set.table;
  const uint32_t k = 5, cx = uint32_t(fx.samples.offset.x) + 10, cy = uint32_t(fx.samples.offset.y) + 10;
  const uint32_t far = t.at(cx, cy, k - 1);
  fx.samples.colour[far] = glm::vec3(std::numeric_limits<float>::quiet_NaN());
  reconstruct_params rp;
  rp.how = method::shepard;
  rp.k = k;
  const frame f = reconstruct(fx.set, fx.samples, rp);
  const glm::vec3 v = f.rgb[size_t(10) * 40 + 10];
  EXPECT_NEAR(v.r, c.r, 1e-6) << "the NaN neighbour's zero weight still poisoned the pixel";
  EXPECT_NEAR(v.b, c.b, 1e-6);
}

TEST(Rbf, RejectsANonPositiveShape) {
  fixture fx(16, 16, {8, 8}, [](float, float) { return glm::vec3(1); });
  reconstruct_params rp;
  rp.how = method::rbf;
  rp.shape = 0;
  EXPECT_THROW(reconstruct(fx.set, fx.samples, rp), std::invalid_argument);
}

}  // namespace
}  // namespace fov
