// FLIP and the foveated FLIP: known answers from the paper's construction.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "fov/flip.h"
#include "fov/metrics.h"

namespace fov {
namespace {

template <class F>
frame image(int w, int h, F colour) {
  frame f;
  f.width = w, f.height = h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) f.rgb.push_back(colour(x, y));
  f.depth.assign(f.rgb.size(), 1.0f);
  return f;
}
frame flat(int w, int h, glm::vec3 c) { return image(w, h, [&](int, int) { return c; }); }

double mean(const error_map& m) {
  double s = 0;
  for (float v : m.value) s += v;
  return s / double(m.value.size());
}

TEST(Flip, IdenticalImagesScoreZero) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<float> u(0, 1);
  const frame a = image(48, 40, [&](int, int) { return glm::vec3(u(gen), u(gen), u(gen)); });
  const error_map m = flip_map(a, a, 20);
  for (float v : m.value) ASSERT_EQ(v, 0.0f);
  spacing_model eye;
  eye.display = {48, 40, 1.0};
  const flip_report r = measure_flip(a, a, eye, {24, 20});
  EXPECT_EQ(r.flip.mean, 0.0);
  EXPECT_EQ(r.foveated.mean, 0.0);
  EXPECT_EQ(r.foveated.p99, 0.0);
}

// The error's scale is set by the largest colour difference, green against blue: flat
// fields of the two score exactly 1 (no features, so the colour term alone).
TEST(Flip, GreenAgainstBlueIsTheMaximum) {
  const error_map m = flip_map(flat(32, 24, {0, 1, 0}), flat(32, 24, {0, 0, 1}), 30);
  for (float v : m.value) ASSERT_NEAR(v, 1.0f, 1e-5f);
}

// A flat colour difference grows with the difference, stays below the maximum, and is
// symmetric; grey against grey has no chroma, black against white is large but < 1.
TEST(Flip, FlatDifferencesGrowAndStayBelowOne) {
  double last = 0;
  for (float g : {0.55f, 0.6f, 0.7f, 0.9f}) {
    const double e = mean(flip_map(flat(16, 16, glm::vec3(g)), flat(16, 16, glm::vec3(0.5f)), 30));
    EXPECT_GT(e, last) << g;
    EXPECT_LT(e, 1.0);
    last = e;
  }
  const double bw = mean(flip_map(flat(16, 16, glm::vec3(1)), flat(16, 16, glm::vec3(0)), 30));
  const double wb = mean(flip_map(flat(16, 16, glm::vec3(0)), flat(16, 16, glm::vec3(1)), 30));
  EXPECT_GT(bw, 0.9);
  EXPECT_LT(bw, 1.0);
  EXPECT_NEAR(bw, wb, 1e-6);
}

// The same-sized error costs more on an edge: FLIP raises the colour error to 1 - feature
// difference. A step edge shifted by one pixel errs only near the edge, and there more
// than a flat change of the same luminance difference does.
TEST(Flip, EdgesAmplifyAndStayLocal) {
  auto step = [](int at) { return image(64, 16, [at](int x, int) { return glm::vec3(x < at ? 0.2f : 0.8f); }); };
  const error_map m = flip_map(step(33), step(32), 20);
  EXPECT_GT(m.value[8 * 64 + 32], 0.5f);
  EXPECT_EQ(m.value[8 * 64 + 5], 0.0f);   // far from the edge: no difference left
  EXPECT_EQ(m.value[8 * 64 + 58], 0.0f);
  const double flat_change = mean(flip_map(flat(64, 16, glm::vec3(0.8f)), flat(64, 16, glm::vec3(0.2f)), 20));
  EXPECT_GT(m.value[8 * 64 + 32], flat_change * 0.9);
}

// Fine detail fades with viewing distance: a one-pixel checker against its mean grey
// scores lower the more pixels a degree holds.
TEST(Flip, FineDetailFadesWithPixelsPerDegree) {
  const frame checker = image(64, 64, [](int x, int y) { return glm::vec3((x + y) % 2 ? 0.9f : 0.1f); });
  const frame grey = image(64, 64, [&](int x, int y) {
    (void)x, (void)y;
    return glm::vec3(0.5f * (0.9f + 0.1f));
  });
  const double near = mean(flip_map(checker, grey, 10)), mid = mean(flip_map(checker, grey, 40)),
               far = mean(flip_map(checker, grey, 160));
  EXPECT_GT(near, mid);
  EXPECT_GT(mid, far);
}

TEST(Flip, RejectsMismatchedFramesAndBadPpd) {
  EXPECT_THROW(flip_map(flat(8, 8, glm::vec3(0)), flat(8, 9, glm::vec3(0)), 20), std::invalid_argument);
  EXPECT_THROW(flip_map(flat(8, 8, glm::vec3(0)), flat(8, 8, glm::vec3(0)), 0), std::invalid_argument);
  EXPECT_THROW(flip_map(flat(8, 8, glm::vec3(0)), flat(8, 8, glm::vec3(0)), std::nan("")), std::invalid_argument);
}

TEST(FoveatedFlip, PpdGrowsAsAcuityFalls) {
  const acuity_params a;
  EXPECT_DOUBLE_EQ(foveated_ppd(20, a, 0), 20);
  // Thesis Eq. 2: fc(0) / fc(e) = (e + e2) / e2.
  EXPECT_NEAR(foveated_ppd(20, a, a.e2), 40, 1e-9);
  EXPECT_NEAR(foveated_ppd(20, a, 3 * a.e2), 80, 1e-9);
}

// Equal to FLIP where the eye looks; below it where acuity has fallen, for noise the
// fovea would see.
TEST(FoveatedFlip, EqualsFlipAtTheGazeAndForgivesThePeriphery) {
  std::mt19937 gen(11);
  std::normal_distribution<float> n(0, 0.15f);
  const int w = 160, h = 120;
  const frame ref = flat(w, h, glm::vec3(0.5f));
  const frame noisy = image(w, h, [&](int, int) { return glm::vec3(0.5f + n(gen)); });
  spacing_model eye;
  eye.display = {w, h, 1.0};
  const gaze_point gaze{80, 60};
  const error_map plain = flip_map(noisy, ref, display_ppd(eye.display));
  const error_map fov = foveated_flip_map(noisy, ref, eye, gaze);
  // The four pixels around the gaze are 0.03 degrees out: their level position is below
  // 0.02, so within a few per cent of level 0.
  for (int y = 59; y <= 60; ++y)
    for (int x = 79; x <= 80; ++x) {
      const size_t i = size_t(y) * w + x;
      EXPECT_NEAR(fov.value[i], plain.value[i], 0.05 * plain.value[i] + 1e-3) << x << "," << y;
    }
  const pooled_error pf = pool_error(fov, eye.display, gaze), pp = pool_error(plain, eye.display, gaze);
  // Acuity halves by 2.3 degrees already: less is seen within 5 degrees, far less beyond 30.
  EXPECT_LT(pf.bands[0], pp.bands[0]);
  EXPECT_LT(pf.bands.back(), 0.5 * pp.bands.back());
  for (size_t b = 1; b + 1 < pf.bands.size(); ++b) EXPECT_LT(pf.bands[b], pf.bands[b - 1]) << b;  // (> 30: corners only)
  // With a flat acuity (huge e2) the foveated FLIP is FLIP everywhere.
  eye.acuity.e2 = 1e9;
  const error_map same = foveated_flip_map(noisy, ref, eye, gaze);
  for (size_t i = 0; i < same.value.size(); ++i) ASSERT_NEAR(same.value[i], plain.value[i], 1e-6f);
}

TEST(PoolError, BandsWorstBandAndPercentile) {
  // A 100x1 map seen from 2 widths with the gaze at x = 0: pixel x is atan((x + 0.5) / 200)
  // out, so the first 17 lie within 5 degrees and none beyond 30 (the last is at 26.4).
  error_map m;
  m.width = 100, m.height = 1;
  for (int x = 0; x < 100; ++x) m.value.push_back(x < 17 ? 0.5f : 0.1f);
  const display_geometry d{100, 1, 2.0};
  const pooled_error p = pool_error(m, d, {0, 0.5});
  EXPECT_NEAR(p.mean, (17 * 0.5 + 83 * 0.1) / 100, 1e-6);
  EXPECT_EQ(p.pixels[0], 17u);
  EXPECT_NEAR(p.bands[0], 0.5, 1e-6);
  EXPECT_NEAR(p.bands[1], 0.1, 1e-6);
  EXPECT_NEAR(p.worst_band, 0.5, 1e-6);
  EXPECT_NEAR(p.p99, 0.5, 1e-6);  // 17 % of the pixels are at 0.5
  EXPECT_EQ(p.pixels.back(), 0u);
  EXPECT_TRUE(std::isnan(p.bands.back()));  // no pixel beyond 30 degrees
  EXPECT_THROW(pool_error(m, {50, 1, 2.0}, {0, 0.5}), std::invalid_argument);  // not the display's size
}

}  // namespace
}  // namespace fov
