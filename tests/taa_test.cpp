#include <cmath>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "fov/acuity.h"
#include "fov/taa.h"
#include "fov/frame.h"

namespace fov {
namespace {

const display_geometry screen{64, 48, 1.0};
const gaze_point centre{32, 24};

// A horizontal ramp in every channel (0.015-0.02 per pixel): an offset of 0.005 lies inside
// each 3x3 neighbourhood's spread (sigma >= 0.007, also at the clamped edges), so the
// history is never clipped and the blend alone sets the rate.
frame ramp() {
  frame f;
  f.width = 64;
  f.height = 48;
  f.rgb.resize(64 * 48);
  f.depth.assign(64 * 48, 5.0f);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) f.rgb[size_t(y) * 64 + x] = glm::vec3(0.1f + 0.02f * x, 0.2f + 0.015f * x, 0.3f + 0.018f * x);
  return f;
}

frame textured(std::mt19937& random, float offset = 0) {
  std::uniform_real_distribution<float> u(0.2f, 0.8f);
  frame f;
  f.width = 64;
  f.height = 48;
  f.rgb.resize(64 * 48);
  f.depth.assign(64 * 48, 5.0f);
  for (glm::vec3& c : f.rgb) c = glm::vec3(u(random), u(random), u(random)) + offset;
  return f;
}

double mean_abs(const frame& a, const frame& b) {
  double s = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) s += std::fabs(a.rgb[i][c] - b.rgb[i][c]);
  return s / (3.0 * a.rgb.size());
}

TEST(Taa, FirstFramePassesThroughAndAStaticViewConvergesGeometrically) {
  const frame b = ramp();
  frame a = b;
  for (glm::vec3& c : a.rgb) c += 0.005f;
  const camera cam = look_at({0, 0, 0}, {0, 0, -1}, 60);
  taa_state state;
  EXPECT_EQ(taa_resolve(state, a, cam, screen, centre).rgb, a.rgb);
  double previous = mean_abs(a, b);
  for (int n = 1; n <= 60; ++n) {
    const double error = mean_abs(taa_resolve(state, b, cam, screen, centre), b);
    if (n <= 5) {
      EXPECT_NEAR(error / previous, 0.9, 0.02) << "frame " << n << ": decays by 1 - alpha";
    }
    previous = error;
  }
  EXPECT_LT(previous, 1.1 * 0.005 * std::pow(0.9, 60)) << "0.005 * 0.9^60 = 9e-6";
}

TEST(Taa, FlickerFallsWithTaa) {
  // A static view whose frames differ by noise (as a drifting gaze's do): the mean absolute
  // frame-to-frame change of the output must fall well below the input's.
  std::mt19937 random(2);
  const frame base = textured(random);
  std::normal_distribution<float> noise(0, 0.05f);
  const camera cam = look_at({0, 0, 0}, {0, 0, -1}, 60);
  taa_state state;
  frame last_in, last_out;
  double flicker_in = 0, flicker_out = 0;
  for (int n = 0; n < 40; ++n) {
    frame f = base;
    for (glm::vec3& c : f.rgb) c += glm::vec3(noise(random), noise(random), noise(random));
    const frame out = taa_resolve(state, f, cam, screen, centre);
    if (n >= 10) flicker_in += mean_abs(f, last_in), flicker_out += mean_abs(out, last_out);
    last_in = f, last_out = out;
  }
  std::cout << "flicker: input " << flicker_in / 30 << ", output " << flicker_out / 30 << "\n";
  EXPECT_LT(flicker_out, 0.5 * flicker_in);
}

TEST(Taa, AGazeJumpTakesTheCurrentFrameWhereEccentricityDropped) {
  std::mt19937 random(3);
  const camera cam = look_at({0, 0, 0}, {0, 0, -1}, 60);
  taa_state state;
  const gaze_point old_gaze{2, 2}, new_gaze{60, 44};
  taa_resolve(state, textured(random), cam, screen, old_gaze);
  const frame now = textured(random);
  const frame out = taa_resolve(state, now, cam, screen, new_gaze);
  int exact = 0, checked = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const double drop = pixel_eccentricity_deg(screen, old_gaze, x, y) -
                          pixel_eccentricity_deg(screen, new_gaze, x, y);
      if (drop < 5) continue;
      ++checked;
      exact += out.rgb[size_t(y) * 64 + x] == now.rgb[size_t(y) * 64 + x];
    }
  EXPECT_GT(checked, 100);
  EXPECT_EQ(exact, checked);
}

}  // namespace
}  // namespace fov
