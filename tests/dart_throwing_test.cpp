#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "fov/dart_throwing.h"
#include "test_sets.h"

namespace fov {
namespace {

using testing::brute_force_violations;
using testing::quick_darts;
using testing::small_model;

TEST(DartThrowing, NoPairCloserThanItsSpacingCheckedExhaustively) {
  for (auto [w, h, v, s] : {std::tuple{64, 48, 1.0, 1.0}, {40, 40, 0.05, 1.0}, {48, 64, 1.0, 3.0},
                            {32, 32, 50.0, 1.0}, {64, 64, 1.0, 0.5}, {1, 1, 1.0, 1.0}}) {
    const spacing_model m = small_model(w, h, v, s);
    const std::vector<point> pts = throw_darts(m, quick_darts());
    ASSERT_FALSE(pts.empty());
    EXPECT_EQ(brute_force_violations(pts), 0u) << w << "x" << h << " v=" << v << " s=" << s;
    EXPECT_EQ(count_spacing_violations(pts, 2 * w, 2 * h), 0u);
    for (const point& p : pts) {
      ASSERT_TRUE(p.x >= 0 && p.x < 2 * w && p.y >= 0 && p.y < 2 * h);
      // The stored spacing is the model's at that position (float-rounded).
      const double d = std::hypot(double(p.x) - w, double(p.y) - h);
      ASSERT_FLOAT_EQ(p.spacing, float(point_spacing_px(m, d)));
    }
  }
}

TEST(DartThrowing, ViolationCounterFindsPlantedViolations) {
  // The checker must be able to fail: plant pairs that are too close.
  // Exact duplicates: each is closer than its spacing to its original and to nothing else.
  const spacing_model m = small_model(100, 80);
  std::vector<point> pts = throw_darts(m, quick_darts());
  const size_t n = pts.size();
  for (size_t i = 0; i < 5; ++i) pts.push_back(pts[i * 97]);
  EXPECT_EQ(count_spacing_violations(pts, 200, 160), 5u);
  EXPECT_EQ(brute_force_violations(pts), 5u);
  pts.resize(n);
  EXPECT_EQ(count_spacing_violations(pts, 200, 160), 0u);
}

TEST(DartThrowing, LargeCanvasHasNoViolationsByGrid) {
  const spacing_model m = small_model(640, 720);
  dart_stats stats;
  const std::vector<point> pts = throw_darts(m, quick_darts(3), &stats);
  EXPECT_EQ(count_spacing_violations(pts, 1280, 1440), 0u);
  EXPECT_EQ(stats.phase1_points + stats.phase2_points, pts.size());
  EXPECT_GT(stats.phase2_points, 0u);
}

// Points per unit area times p^2 in rings around the centre: a saturated Poisson-disc
// set with minimum distance p has density about 0.69 / p^2 (random sequential
// adsorption of discs of diameter p jams at 54.7 % coverage: 0.547 * 4 / pi = 0.697).
TEST(DartThrowing, DensityFollowsTheModelInEveryRing) {
  const int w = 640, h = 720;
  const spacing_model m = small_model(w, h);
  const std::vector<point> pts = throw_darts(m, quick_darts(11, 8000));
  const double ring = 40;
  const int rings = int(std::hypot(w, h) / ring);
  std::vector<double> count(rings, 0), area(rings, 0), p2(rings, 0);
  for (const point& p : pts) {
    const int r = int(std::hypot(p.x - w, p.y - h) / ring);
    if (r < rings) count[r] += 1;
  }
  // Ring area inside the canvas and the model's mean 1/p^2 over it, from pixel centres.
  for (int y = 0; y < 2 * h; ++y)
    for (int x = 0; x < 2 * w; ++x) {
      const double d = std::hypot(x + 0.5 - w, y + 0.5 - h);
      const int r = int(d / ring);
      if (r >= rings) continue;
      area[r] += 1;
      const double p = point_spacing_px(m, d);
      p2[r] += 1 / (p * p);
    }
  for (int r = 0; r < rings; ++r) {
    if (area[r] < 20000) continue;  // too few points in the outermost partial rings
    const double normalised = count[r] / p2[r];
    EXPECT_NEAR(normalised, 0.69, 0.69 * 0.06) << "ring " << r * ring << ".." << (r + 1) * ring << " px";
  }
}

TEST(DartThrowing, MortonOrderHolds) {
  const std::vector<point> pts = throw_darts(small_model(300, 200), quick_darts());
  for (size_t i = 1; i < pts.size(); ++i)
    ASSERT_LE(morton_code(pts[i - 1].x, pts[i - 1].y), morton_code(pts[i].x, pts[i].y)) << i;
  // Z-order: (1,0) < (0,1) < (1,1), and quadrants nest.
  EXPECT_LT(morton_code(1, 0), morton_code(0, 1));
  EXPECT_LT(morton_code(0, 1), morton_code(1, 1));
  EXPECT_LT(morton_code(1.9f, 1.9f), morton_code(2.0f, 0.0f));
}

TEST(DartThrowing, DeterministicForAnyThreadCount) {
  const spacing_model m = small_model(320, 240);
  std::vector<point> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = throw_darts(m, quick_darts(5));
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = throw_darts(m, quick_darts(5));
  }
  ASSERT_EQ(one.size(), two.size());
  for (size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one[i].x, two[i].x);
    ASSERT_EQ(one[i].y, two[i].y);
    ASSERT_EQ(one[i].spacing, two[i].spacing);
  }
  const std::vector<point> other = throw_darts(m, quick_darts(6));
  EXPECT_FALSE(other.size() == one.size() && other[0].x == one[0].x && other[0].y == one[0].y);
}

TEST(FovealGrid, EveryGridPixelHoldsOnePointAtItsCentreAndDartsKeepTheirSpacing) {
  const spacing_model m = testing::partial_grid_model();
  dart_params params = testing::grid_darts();
  dart_stats stats;
  const std::vector<point> pts = throw_darts(m, params, &stats);
  const uint32_t cw = 2 * m.display.width, ch = 2 * m.display.height;
  std::vector<int> held(size_t(cw) * ch, 0);
  uint64_t grid_pixels = 0, darts_in_grid_pixels = 0;
  for (uint32_t y = 0; y < ch; ++y)
    for (uint32_t x = 0; x < cw; ++x) grid_pixels += is_grid_pixel(m, params, x, y);
  pointset set;
  set.model = m, set.darts = params;
  for (const point& p : pts) {
    const uint32_t px = uint32_t(p.x), py = uint32_t(p.y);
    if (is_grid_point(set, p)) {
      ++held[size_t(py) * cw + px];
      EXPECT_EQ(p.spacing, 1.0f);
    } else {
      // No dart inside a grid pixel, anywhere in it: its grid point is the pixel's value, so a
      // dart there would be traced and never weigh (the grid fovea's hidden darts, issue 24).
      darts_in_grid_pixels += is_grid_pixel(m, params, px, py);
      ASSERT_EQ(in_grid_pixel(m, params, p.x, p.y), is_grid_pixel(m, params, px, py));
      // A dart keeps the model's spacing at its position, and its spacing is above the grid's
      // almost everywhere (only at the disc's rim may a dart sit where the model asks for less).
      const double d = std::hypot(double(p.x) - m.display.width, double(p.y) - m.display.height);
      ASSERT_FLOAT_EQ(p.spacing, float(point_spacing_px(m, d)));
    }
  }
  // The fast test gives is_grid_point's answers: for every point, and for every pixel centre
  // and a point a hair beside each.
  set.points = pts;
  const grid_test fast(set);
  for (const point& p : pts) ASSERT_EQ(fast(p), is_grid_point(set, p));
  for (uint32_t y = 0; y < ch; ++y)
    for (uint32_t x = 0; x < cw; ++x) {
      const point centre{float(x) + 0.5f, float(y) + 0.5f, 1.0f};
      ASSERT_EQ(fast(centre), is_grid_point(set, centre)) << x << "," << y;
      ASSERT_EQ(fast(centre), is_grid_pixel(m, params, x, y));
      const point beside{std::nextafter(centre.x, 1e9f), centre.y, 1.0f};
      ASSERT_FALSE(fast(beside));
    }
  // The grid is a proper part of the canvas: a disc, with darts around it.
  EXPECT_GT(grid_pixels, 5000u);
  EXPECT_LT(grid_pixels, uint64_t(cw) * ch / 2);
  EXPECT_EQ(stats.grid_points, grid_pixels);
  EXPECT_EQ(darts_in_grid_pixels, 0u);
  for (uint32_t y = 0; y < ch; ++y)
    for (uint32_t x = 0; x < cw; ++x)
      ASSERT_EQ(held[size_t(y) * cw + x], is_grid_pixel(m, params, x, y) ? 1 : 0) << x << "," << y;
  EXPECT_EQ(pts.size(), stats.grid_points + stats.phase1_points + stats.phase2_points);
  EXPECT_GT(stats.phase1_points, 1000u);
  // The spacing rule holds across the seam (every pair, exhaustively) and the set is maximal.
  EXPECT_EQ(brute_force_violations(pts), 0u);
  EXPECT_EQ(count_spacing_violations(pts, cw, ch), 0u);
  EXPECT_LT(stats.free_fraction, 1e-3);
  // The ring just outside the grid is as dense as the dart rule allows: no gap along the rim.
  // Darts at spacing p reach at least 0.5 / p^2 points per pixel in a maximal set.
  double rim = -1;
  for (uint32_t x = uint32_t(m.display.width); x < cw; ++x)
    if (!is_grid_pixel(m, params, x, uint32_t(m.display.height))) {
      rim = x + 0.5 - m.display.width;
      break;
    }
  ASSERT_GT(rim, 10.0);
  uint64_t in_ring = 0;
  for (const point& p : pts) {
    const double d = std::hypot(double(p.x) - m.display.width, double(p.y) - m.display.height);
    in_ring += d >= rim && d < rim + 4;
  }
  const double ring_area = M_PI * ((rim + 4) * (rim + 4) - rim * rim);
  const double p_outer = point_spacing_px(m, rim + 4);
  EXPECT_GT(double(in_ring) / ring_area, 0.5 / (p_outer * p_outer)) << in_ring << " points in the rim ring";
  // More grid spacing, a larger grid; and the thesis's layout has none.
  params.grid_spacing = 1.5;
  dart_stats wider;
  throw_darts(m, params, &wider);
  EXPECT_GT(wider.grid_points, stats.grid_points);
  dart_stats none;
  throw_darts(m, testing::quick_darts(), &none);
  EXPECT_EQ(none.grid_points, 0u);
  params.grid_spacing = 0.2;
  EXPECT_THROW(throw_darts(m, params), std::invalid_argument);
}

TEST(FovealGrid, DeterministicForAnyThreadCount) {
  std::vector<point> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = throw_darts(testing::partial_grid_model(), testing::grid_darts(5));
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = throw_darts(testing::partial_grid_model(), testing::grid_darts(5));
  }
  ASSERT_EQ(one.size(), two.size());
  for (size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one[i].x, two[i].x);
    ASSERT_EQ(one[i].y, two[i].y);
  }
}

TEST(DartThrowing, MoreSaturationLeavesLessFreeArea) {
  const spacing_model m = small_model(256, 256);
  dart_stats loose, tight;
  const auto a = throw_darts(m, quick_darts(1, 200), &loose);
  const auto b = throw_darts(m, quick_darts(1, 8000), &tight);
  EXPECT_GT(b.size(), a.size());
  EXPECT_LT(tight.free_fraction, loose.free_fraction);
  EXPECT_LT(tight.free_fraction, 5e-4);
  EXPECT_GT(loose.free_fraction, 0.0);  // the estimate sees a loose set is not maximal
}

TEST(DartThrowing, ExtremeParametersWorkOrFailClearly) {
  // 8K: canvas 15360 x 8640; the grid and spacing stay finite (the table is tested in knn_table_test).
  const spacing_model m8k = small_model(7680, 4320);
  EXPECT_EQ(validate(m8k), "");
  EXPECT_TRUE(std::isfinite(point_spacing_px(m8k, std::hypot(7680.0, 4320.0))));
  // s = 10 on a small screen still gives a valid, violation-free set.
  const auto sparse = throw_darts(small_model(128, 128, 1.0, 10.0), quick_darts());
  EXPECT_GT(sparse.size(), 10u);
  EXPECT_EQ(count_spacing_violations(sparse, 256, 256), 0u);
  // Nonsense parameters are rejected with the reason.
  try {
    throw_darts(small_model(64, 64, -1.0), quick_darts());
    FAIL() << "negative viewing distance accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("viewing distance"), std::string::npos);
  }
  dart_params zero = quick_darts();
  zero.saturation_rejections = 0;
  EXPECT_THROW(throw_darts(small_model(64, 64), zero), std::invalid_argument);
}

}  // namespace
}  // namespace fov
