// FovVideoVDP (measure/fvvdp.h): the published implementation's values on
// ../shared/metric-validation within 0.1 JOD, and properties with known answers: identical
// inputs give 10, JOD falls with noise and blur, a peripheral distortion costs less
// foveated than not, flicker costs more than the same noise held still.
#include <cmath>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "fov/fvvdp.h"
#include "jod_validation.h"

namespace fov {
namespace {

// 128 x 128 pixels seen from 10 widths: 22.34 pixels per degree at the centre, the FOVE
// eye's and the validation set's.
const display_geometry small{128, 128, 10.0};

// A textured reference: two gratings and a smooth ramp, display values in 0.1..0.9.
frame texture(const display_geometry& d = small) {
  frame f;
  f.width = d.width, f.height = d.height;
  for (int y = 0; y < d.height; ++y)
    for (int x = 0; x < d.width; ++x) {
      const float v = 0.5f + 0.2f * std::sin(0.45f * x) * std::cos(0.3f * y) + 0.2f * (float(x + y) / (d.width + d.height) - 0.5f);
      f.rgb.emplace_back(v * v);  // roughly linear light of display value v
    }
  return f;
}

frame with_noise(frame f, float sigma, uint32_t seed, int x0 = 0, int y0 = 0, int x1 = 1 << 30, int y1 = 1 << 30) {
  std::mt19937 random(seed);
  std::normal_distribution<float> n(0, sigma);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      if (x >= x0 && x < x1 && y >= y0 && y < y1) f.rgb[size_t(y) * f.width + x] += glm::vec3(n(random));
  return f;
}

frame box_blur(const frame& f, int radius) {
  frame out = f;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      glm::vec3 s(0);
      int n = 0;
      for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
          const int xx = std::clamp(x + dx, 0, f.width - 1), yy = std::clamp(y + dy, 0, f.height - 1);
          s += f.rgb[size_t(yy) * f.width + xx], ++n;
        }
      out.rgb[size_t(y) * f.width + x] = s / float(n);
    }
  return out;
}

TEST(Fvvdp, PublishedValuesWithinATenthOfAJod) {
  const std::filesystem::path dir = std::filesystem::path(FOV_SOURCE_DIR) / "../shared/metric-validation";
  if (!std::filesystem::exists(dir / "jod-reference.json")) GTEST_SKIP() << "../shared/metric-validation is absent";
  const jod_validation v = validate_jod(dir.string());
  // 24 image pairs in three views, 2 videos in two.
  EXPECT_EQ(v.rows.size(), 24u * 3 + 2 * 2);
  for (const jod_check& c : v.rows) EXPECT_NEAR(c.ours, c.published, 0.1) << c.test << " " << c.view;
  EXPECT_LE(v.worst, 0.1);
}

TEST(Fvvdp, IdenticalInputsGiveTen) {
  const frame a = texture();
  const fvvdp_result r = fvvdp_image(a, a, small, {64, 64});
  EXPECT_EQ(r.jod, 10.0);
  EXPECT_EQ(r.jod_nonfoveated, 10.0);
  EXPECT_EQ(r.q, 0.0);
  EXPECT_EQ(r.frames, 1);
  EXPECT_EQ(r.bands, 5);  // 11.2, 3.6, 1.8, 0.9 and 0.45 cpd at 22.34 pixels per degree
}

TEST(Fvvdp, JodFallsWithNoiseAndBlur) {
  const frame ref = texture();
  double last = 10, last_nf = 10;
  for (float sigma : {0.005f, 0.02f, 0.05f, 0.1f}) {
    const fvvdp_result r = fvvdp_image(with_noise(ref, sigma, 7), ref, small, {64, 64});
    EXPECT_LT(r.jod, last) << sigma;
    EXPECT_LT(r.jod_nonfoveated, last_nf) << sigma;
    EXPECT_LE(r.jod_nonfoveated, r.jod) << sigma;  // every pixel seen foveally is the stricter view
    last = r.jod, last_nf = r.jod_nonfoveated;
  }
  EXPECT_LT(last, 9.0);  // strong noise is plainly visible
  last = 10;
  for (int radius : {1, 2, 4}) {
    const fvvdp_result r = fvvdp_image(box_blur(ref, radius), ref, small, {64, 64});
    EXPECT_LT(r.jod, last) << radius;
    last = r.jod;
  }
}

TEST(Fvvdp, PeripheralDistortionCostsLessFoveatedThanAtTheGaze) {
  // Seen from 2.5 widths the 128-pixel screen spans 22.6 degrees: its corners lie 15
  // degrees from a gaze at the opposite corner.
  const display_geometry wide{128, 128, 2.5};
  const frame ref = texture(wide);
  const frame corner = with_noise(ref, 0.06f, 3, 96, 96, 128, 128);
  const fvvdp_result far = fvvdp_image(corner, ref, wide, {8, 8}), near = fvvdp_image(corner, ref, wide, {112, 112});
  EXPECT_GT(far.jod, far.jod_nonfoveated + 0.05);
  EXPECT_GT(far.jod, near.jod + 0.05);
  EXPECT_NEAR(far.jod_nonfoveated, near.jod_nonfoveated, 1e-9);  // the gaze does not matter non-foveated
}

TEST(Fvvdp, FlickerCostsMoreThanTheSameNoiseHeldStill) {
  const frame ref = texture();
  fvvdp flicker(small, 60), still(small, 60);
  const frame fixed = with_noise(ref, 0.03f, 11);
  for (int i = 0; i < 10; ++i) {
    flicker.add(with_noise(ref, 0.03f, 100 + uint32_t(i)), ref, {64, 64});
    still.add(fixed, ref, {64, 64});
  }
  const fvvdp_result f = flicker.result(), s = still.result();
  EXPECT_EQ(f.frames, 10);
  EXPECT_LT(f.jod, s.jod - 0.1);
  EXPECT_LT(f.jod_nonfoveated, s.jod_nonfoveated - 0.1);
  // Noise held still is an image: the video's sustained channel sees it as the image does.
  const fvvdp_result image = fvvdp_image(fixed, ref, small, {64, 64});
  EXPECT_NEAR(s.jod, image.jod, 0.05);
}

TEST(Fvvdp, CsfPeaksAtMidFrequenciesAndFallsWithEccentricity) {
  // Band-pass at 100 cd/m^2: for the metric's 1.5-cycle Gabors the peak lies near 1 cycle
  // per degree.
  double best = 0, best_rho = 0;
  for (double rho = 0.25; rho <= 32; rho *= 1.1)
    if (const double s = fvvdp_csf(rho, 0, 100, 0); s > best) best = s, best_rho = rho;
  EXPECT_GT(best_rho, 0.7);
  EXPECT_LT(best_rho, 4.0);
  EXPECT_GT(best, 2 * fvvdp_csf(0.25, 0, 100, 0));
  EXPECT_GT(best, 10 * fvvdp_csf(16, 0, 100, 0));
  EXPECT_GT(fvvdp_csf(8, 0, 100, 0), fvvdp_csf(8, 0, 100, 10));
  EXPECT_GT(fvvdp_csf(8, 0, 100, 10), fvvdp_csf(8, 0, 100, 30));
  EXPECT_GT(fvvdp_csf(4, 0, 100, 0), fvvdp_csf(4, 0, 1, 0));  // more light, more sensitivity
  EXPECT_LT(fvvdp_csf(16, 5, 100, 0), fvvdp_csf(16, 0, 100, 0));  // the transient channel is coarser
}

TEST(Fvvdp, RefusesWhatItCannotMeasure) {
  const frame a = texture();
  EXPECT_THROW(fvvdp(display_geometry{4, 128, 1.0}), std::invalid_argument);
  EXPECT_THROW(fvvdp(small, 3), std::invalid_argument);
  EXPECT_THROW(fvvdp(small, std::nan("")), std::invalid_argument);
  display_photometry dark;
  dark.peak = 0;
  EXPECT_THROW(fvvdp(small, 0, dark), std::invalid_argument);
  EXPECT_NE(photometry_problem(dark).find("peak luminance"), std::string::npos);
  fvvdp image(small);
  image.add(a, a, {1, 1});
  EXPECT_THROW(image.add(a, a, {1, 1}), std::invalid_argument);  // an image comparison takes one pair
  fvvdp other(display_geometry{64, 64, 10.0});
  EXPECT_THROW(other.add(a, a, {1, 1}), std::invalid_argument);  // not the display's size
}

}  // namespace
}  // namespace fov
