// measure/: PSNR/SSIM and the foveated RMSE by eccentricity band, the acuity weight, the
// luminance change flicker is measured by, each band's share of geometry, Pareto fronts and
// the equal-quality speedup.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "fov/metrics.h"
#include "fov/pareto.h"
#include "fov/speedup.h"

namespace fov {
namespace {

frame flat(int w, int h, float v) {
  frame f;
  f.width = w;
  f.height = h;
  f.rgb.assign(size_t(w) * h, glm::vec3(v));
  return f;
}

float linear_of_byte(int b) {
  const float s = float(b) / 255;
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

// The thesis's three bands (< 5, 5-30, > 30 degrees) of measure_error.
error_report thesis_bands(const frame& test, const frame& reference, const display_geometry& d, gaze_point gaze) {
  spacing_model eye;
  eye.display = d;
  return measure_error(test, reference, eye, gaze, {5, 30});
}

TEST(Metrics, IdenticalFramesAreInfinitelyClose) {
  const frame a = flat(32, 24, 0.3f);
  const error_report c = thesis_bands(a, a, {32, 24, 1.0}, {16, 12});
  EXPECT_TRUE(std::isinf(c.overall.psnr));
  EXPECT_NEAR(c.overall.ssim, 1.0, 1e-9);
  EXPECT_EQ(c.overall.pixels, 32u * 24u);
}

TEST(Metrics, AKnownOffsetGivesAKnownPsnr) {
  // Displayed bytes 0 against 10 everywhere: MSE 100, PSNR = 10 log10(255^2 / 100) = 28.1308 dB.
  const frame a = flat(32, 24, 0.0f), b = flat(32, 24, linear_of_byte(10));
  const error_report c = thesis_bands(a, b, {32, 24, 1.0}, {16, 12});
  EXPECT_NEAR(c.overall.psnr, 28.1308, 1e-3);
  EXPECT_NEAR(c.bands[0].psnr, 28.1308, 1e-3);
}

TEST(Metrics, NoiseLowersSsimAndPsnrAsExpected) {
  // Uniform noise of +-20 display levels: MSE = 20^2 / 3 = 133.3 -> PSNR 26.88 dB.
  frame a = flat(64, 64, linear_of_byte(128)), b = a;
  std::mt19937 random(1);
  std::uniform_int_distribution<int> noise(-20, 20);
  double mse = 0;
  for (glm::vec3& c : b.rgb)
    for (int ch = 0; ch < 3; ++ch) {
      const int n = noise(random);
      c[ch] = linear_of_byte(128 + n);
      mse += n * n;
    }
  mse /= 3.0 * 64 * 64;
  const error_report c = thesis_bands(b, a, {64, 64, 1.0}, {32, 32});
  EXPECT_NEAR(c.overall.psnr, 10 * std::log10(255.0 * 255.0 / mse), 1e-6);
  EXPECT_NEAR(c.overall.psnr, 26.88, 0.3);
  EXPECT_LT(c.overall.ssim, 0.9);
  EXPECT_GT(c.overall.ssim, 0.0);
}

TEST(Metrics, EccentricityBandsOnATinyScreen) {
  // 100 px wide at v = 1: 5 deg at 8.75 px, 30 deg at 57.7 px from the gaze.
  const display_geometry d{100, 100, 1.0};
  EXPECT_NEAR(pixel_eccentricity_deg(d, {0.5, 0.5}, 0, 0), 0.0, 1e-12);
  EXPECT_NEAR(pixel_eccentricity_deg(d, {0.5, 0.5}, 100 - 1, 0), std::atan(99.0 / 100) * 180 / M_PI, 1e-9);
  const frame a = flat(100, 100, 0.2f);
  const error_report c = thesis_bands(a, a, d, {0, 0});
  // Count pixel centres within 8.749 px and 57.735 px of the corner gaze.
  uint64_t fovea = 0, mid = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) {
      const double r = std::hypot(x + 0.5, y + 0.5);
      fovea += r < 100 * std::tan(5 * M_PI / 180);
      mid += r >= 100 * std::tan(5 * M_PI / 180) && r < 100 * std::tan(30 * M_PI / 180);
    }
  EXPECT_EQ(c.bands[0].pixels, fovea);
  EXPECT_EQ(c.bands[1].pixels, mid);
  EXPECT_EQ(c.bands[0].pixels + c.bands[1].pixels + c.bands[2].pixels, 10000u);
  EXPECT_GT(c.bands[2].pixels, 0u);
}

TEST(Metrics, FiveBandsProfileAndFoveatedErrorOfAKnownOffset) {
  // Bytes 100 against 110 everywhere: every band and bin has RMSE 10/255, and so has the
  // foveated error (a weighted mean of equal errors).
  const display_geometry d{100, 100, 1.0};
  spacing_model eye;
  eye.display = d;
  eye.scale = 2.5;  // ignored: the weight is the eye's
  const frame a = flat(100, 100, linear_of_byte(100)), b = flat(100, 100, linear_of_byte(110));
  const error_report r = measure_error(a, b, eye, {0, 0});
  ASSERT_EQ(r.bands.size(), 5u);
  uint64_t pixels = 0;
  std::vector<uint64_t> expected(5, 0);
  const double edges[4] = {5, 10, 20, 30};
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) {
      const double e = std::atan(std::hypot(x + 0.5, y + 0.5) / 100) * 180 / M_PI;
      ++expected[size_t(std::upper_bound(edges, edges + 4, e) - edges)];
    }
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(r.bands[i].pixels, expected[i]) << "band " << i;
    EXPECT_NEAR(r.bands[i].psnr, 28.1308, 1e-3) << "band " << i;
    pixels += r.bands[i].pixels;
  }
  EXPECT_EQ(pixels, 10000u);
  EXPECT_NEAR(r.foveated_error, 10.0 / 255, 1e-9);
  EXPECT_NEAR(r.foveated_psnr, 28.1308, 1e-3);
  ASSERT_FALSE(r.profile_rmse.empty());
  for (size_t i = 0; i < r.profile_rmse.size(); ++i)
    if (r.profile_pixels[i]) {
      EXPECT_NEAR(r.profile_rmse[i], 10.0 / 255, 1e-9) << "bin " << i;
    }
  // The corner gaze sees 0 .. 54.7 degrees: 22 bins of 2.5 degrees.
  EXPECT_EQ(r.profile_rmse.size(), 22u);
}

TEST(Metrics, FoveatedErrorWeighsFovealErrorsMore) {
  // The same error next to the gaze or 45 degrees away, on a 1280-px-wide screen at v = 1
  // (where the weight falls to about 0.17): the foveal one counts more.
  const display_geometry d{1280, 64, 1.0};
  spacing_model eye;
  eye.display = d;
  const frame ref = flat(1280, 64, linear_of_byte(100));
  frame near_gaze = ref, far_from_gaze = ref;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      near_gaze.rgb[size_t(y) * 1280 + x] = glm::vec3(linear_of_byte(140));
      far_from_gaze.rgb[size_t(y) * 1280 + 1279 - x] = glm::vec3(linear_of_byte(140));
    }
  const error_report a = measure_error(near_gaze, ref, eye, {0, 32}), b = measure_error(far_from_gaze, ref, eye, {0, 32});
  EXPECT_NEAR(a.overall.psnr, b.overall.psnr, 1e-9);  // equal plain error
  EXPECT_GT(a.foveated_error, 2 * b.foveated_error);
}

TEST(Metrics, AcuityWeightIsOneInTheFoveaAndFalls) {
  spacing_model eye;  // FOVE-like defaults: 1280 px at v = 1
  EXPECT_DOUBLE_EQ(acuity_weight(eye, 0), 1.0);
  double last = 1;
  for (double e = 1; e <= 60; e += 1) {
    const double w = acuity_weight(eye, e);
    EXPECT_LE(w, last);
    EXPECT_GT(w, 0);
    last = w;
  }
  EXPECT_LT(acuity_weight(eye, 60), 0.2);
  // Where fc = fd / 2 the weight is 1/2: fc = e2 ln(1/CT0) / ((e + e2) alpha).
  const double fd = display_nyquist_cpd(eye.display), e2 = eye.acuity.e2;
  const double e_half = e2 * std::log(1 / eye.acuity.ct0) / (eye.acuity.alpha * fd / 2) - e2;
  EXPECT_NEAR(acuity_weight(eye, e_half), 0.5, 1e-9);
}

TEST(Metrics, LuminanceChangeOfAKnownStep) {
  const frame a = flat(8, 8, linear_of_byte(100)), b = flat(8, 8, linear_of_byte(110));
  EXPECT_EQ(mean_luminance_change(a, a), 0.0);
  EXPECT_NEAR(mean_luminance_change(a, b), 10.0 / 255, 1e-6);
}

TEST(Metrics, MismatchedSizesAreRejected) {
  EXPECT_THROW(thesis_bands(flat(4, 4, 0), flat(4, 5, 0), {4, 4, 1.0}, {2, 2}), std::invalid_argument);
}

TEST(Coverage, SharesOfGeometryPerBand) {
  frame f;
  f.width = 100, f.height = 1;
  f.rgb.assign(100, glm::vec3(0));
  for (int x = 0; x < 100; ++x) f.depth.push_back(x < 5 ? 1.0f : std::numeric_limits<float>::infinity());
  // Seen from 2 widths with the gaze at x = 0: the first 17 pixels lie within 5 degrees.
  const std::vector<double> c = geometry_coverage(f, {100, 1, 2.0}, {0, 0.5});
  ASSERT_EQ(c.size(), 5u);
  EXPECT_NEAR(c[0], 5.0 / 17.0, 1e-12);
  EXPECT_EQ(c[1], 0.0);
  EXPECT_TRUE(std::isnan(c[4]));  // no pixel beyond 30 degrees
  f.depth.clear();
  for (double v : geometry_coverage(f, {100, 1, 2.0}, {0, 0.5})) EXPECT_TRUE(std::isnan(v));
}

TEST(Pareto, KeepsOnlyUndominatedPointsSortedByTime) {
  // (time, error): b dominates d; e ties a in time with more error; f is NaN.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> x = {1, 2, 4, 3, 1, 5, nan, 8};
  const std::vector<double> y = {9, 5, 1, 6, 10, 1, 0, 0.5};
  //                              a  b  c  d  e   f  g    h
  const std::vector<size_t> front = pareto_front(x, y);
  EXPECT_EQ(front, (std::vector<size_t>{0, 1, 2, 7}));  // a, b, c, h (f ties c's error but is slower)
  EXPECT_TRUE(pareto_front({}, {}).empty());
}

// Two fronts with known times: the baseline reaches error 0.1 in 40 ms, foveation in 10.
TEST(EqualError, SpeedupAlongBothFronts) {
  const std::vector<std::pair<double, double>> fov = {{10, 0.1}, {20, 0.05}}, base = {{10, 0.4}, {40, 0.1}, {160, 0.025}};
  EXPECT_DOUBLE_EQ(time_at_error(fov, 0.1), 10);
  EXPECT_NEAR(time_at_error(fov, 0.075), std::sqrt(10.0 * 20.0), 1e-9);  // halfway: the geometric mean
  EXPECT_NEAR(equal_error_speedup(fov, base, 0.1), 4.0, 1e-12);
  EXPECT_TRUE(std::isnan(time_at_error(fov, 0.2)));   // worse than the front's worst: not on it
  EXPECT_TRUE(std::isnan(time_at_error(fov, 0.01)));  // better than its best
  // 0.05 lies two thirds of the way from 0.1 to 0.025: log time two thirds of the way from 40 to 160 ms.
  EXPECT_NEAR(equal_error_speedup(fov, base, 0.05), std::pow(40.0, 1 / 3.0) * std::pow(160.0, 2 / 3.0) / 20, 1e-9);
}


TEST(ChainedSpeedup, ConstantSamplesGiveAnExactInterval) {
  const speedup_interval a = chained_speedup({2, 2, 2}, {1.5, 1.5});
  EXPECT_DOUBLE_EQ(a.estimate, 3.0);
  EXPECT_DOUBLE_EQ(a.lo, 3.0);
  EXPECT_DOUBLE_EQ(a.hi, 3.0);
  EXPECT_FALSE(a.contains_one());
  EXPECT_DOUBLE_EQ(chained_speedup({0.5, 0.5}).estimate, 0.5);  // no ladder: the same frame
  EXPECT_TRUE(std::isnan(chained_speedup({}).estimate));
}

TEST(ChainedSpeedup, SpreadWidensTheIntervalAroundTheMedians) {
  // Paired ratios spread around 1.2, ladder around 1: the interval holds the estimate and,
  // with ratios on both sides of 1, contains 1.
  const std::vector<double> paired{0.9, 1.1, 1.2, 1.3, 1.6}, ladder{0.95, 1.0, 1.05};
  const speedup_interval s = chained_speedup(paired, ladder);
  EXPECT_DOUBLE_EQ(s.estimate, 1.2);
  EXPECT_LT(s.lo, s.estimate);
  EXPECT_GT(s.hi, s.estimate);
  EXPECT_TRUE(s.contains_one());
  EXPECT_GE(s.lo, 0.9 * 0.95);
  EXPECT_LE(s.hi, 1.6 * 1.05);
  // Seeded: the same samples give the same interval; more samples of the same spread narrow it.
  const speedup_interval again = chained_speedup(paired, ladder);
  EXPECT_EQ(again.lo, s.lo);
  EXPECT_EQ(again.hi, s.hi);
  std::vector<double> many;
  for (int i = 0; i < 8; ++i) many.insert(many.end(), paired.begin(), paired.end());
  const speedup_interval narrow = chained_speedup(many, ladder);
  EXPECT_LT(narrow.hi - narrow.lo, s.hi - s.lo);
}

}  // namespace
}  // namespace fov
