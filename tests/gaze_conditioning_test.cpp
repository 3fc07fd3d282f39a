// The gaze's conditioning: confidence threshold, the 1-euro filter, I-VT saccades and the
// dropout policy, on synthetic samples with known answers.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "gaze_conditioning.h"

namespace fov {
namespace {

// FOVE's geometry: 1280 pixels across, seen from one width (about 22 pixels per degree).
const display_geometry fove{1280, 1440, 1.0};

gaze_sample at(double x, double y, double t_ms, double confidence = 1) {
  gaze_sample s;
  s.x = x, s.y = y, s.t_ms = t_ms, s.confidence = confidence;
  return s;
}

TEST(GazeConditioning, DropsLowConfidenceSamples) {
  gaze_conditioner c({}, fove, true);
  gaze_estimate e = c.update(0, {at(100, 100, 0, 0.9), at(900, 900, 1, 0.3)});
  EXPECT_EQ(e.at.x, 100);
  EXPECT_EQ(c.low_confidence, 1u);
  EXPECT_EQ(e.fresh, 1u);
}

TEST(GazeConditioning, OneEuroSmoothsJitterAndFollowsAMove) {
  gaze_conditioning p;
  p.min_cutoff_hz = 1, p.beta = 0.05, p.saccade_deg_s = 0;
  gaze_conditioner smooth(p, fove, false), raw({}, fove, false);
  std::mt19937 rng(1);
  std::normal_distribution<double> jitter(0, 5);  // pixels, a fixation's measurement noise
  double sd_smooth = 0, sd_raw = 0;
  const int n = 240;  // 2 s at 120 Hz
  for (int i = 0; i < n; ++i) {
    const gaze_sample s = at(640 + jitter(rng), 720 + jitter(rng), i * 1000.0 / 120);
    const gaze_estimate a = smooth.update(s.t_ms, {s}), b = raw.update(s.t_ms, {s});
    if (i >= n / 2) sd_smooth += std::pow(a.at.x - 640, 2), sd_raw += std::pow(b.at.x - 640, 2);
  }
  sd_smooth = std::sqrt(sd_smooth / (n / 2)), sd_raw = std::sqrt(sd_raw / (n / 2));
  EXPECT_LT(sd_smooth, 0.4 * sd_raw) << "smoothed " << sd_smooth << " px, raw " << sd_raw << " px";
  // A slow pursuit (10 deg/s, about 220 px/s): the speed raises the cutoff, so the lag stays small.
  gaze_estimate e;
  for (int i = 0; i < 120; ++i) e = smooth.update(i * 1000.0 / 120 + 2000, {at(640 + 220.0 * i / 120, 720, i * 1000.0 / 120 + 2000)});
  EXPECT_NEAR(e.at.x, 640 + 220.0 * 119 / 120, 15);
}

TEST(GazeConditioning, IvtFindsASaccadeAndItsLanding) {
  gaze_conditioning p;  // 30 deg/s
  gaze_conditioner c(p, fove, true);
  double t = 0;
  gaze_estimate e;
  for (int i = 0; i < 10; ++i, t += 8) e = c.update(t, {at(300, 700, t)});  // fixation
  EXPECT_EQ(e.state, gaze_state::tracking);
  // A 20-degree saccade (about 440 px) in 40 ms: 500 deg/s.
  for (int i = 1; i <= 5; ++i, t += 8) {
    e = c.update(t, {at(300 + 88.0 * i, 700, t)});
    EXPECT_EQ(e.state, gaze_state::saccade);
    EXPECT_FALSE(e.landed);
  }
  e = c.update(t, {at(740, 700, t)});  // still: landed
  EXPECT_TRUE(e.landed);
  EXPECT_EQ(e.state, gaze_state::tracking);
  EXPECT_EQ(e.saccade_onset.x, 300);
  EXPECT_EQ(e.at.x, 740);
  EXPECT_EQ(c.saccades, 1u);
  // A drift of 1 pixel per 8 ms (about 5.7 deg/s) is no saccade.
  for (int i = 0; i < 20; ++i, t += 8) e = c.update(t, {at(740 + i, 700, t)});
  EXPECT_EQ(c.saccades, 1u);
  EXPECT_EQ(e.state, gaze_state::tracking);
}

TEST(GazeConditioning, HoldsThenFallsBackToTheCentreAndCountsDropouts) {
  gaze_conditioning p;
  p.hold_ms = 150;
  gaze_conditioner c(p, fove, true);
  gaze_estimate e = c.update(0, {});
  EXPECT_EQ(e.state, gaze_state::safe);  // nothing yet
  EXPECT_EQ(c.dropouts, 0u);
  e = c.update(10, {at(100, 200, 10)});
  EXPECT_EQ(e.state, gaze_state::tracking);
  e = c.update(100, {});
  EXPECT_EQ(e.state, gaze_state::holding);
  EXPECT_EQ(e.at.x, 100);
  EXPECT_DOUBLE_EQ(e.age_ms, 90);
  e = c.update(161, {at(100, 200, 161, 0.1)});  // a blink: low confidence is no gaze
  EXPECT_EQ(e.state, gaze_state::safe);
  EXPECT_EQ(e.at.x, 640);
  EXPECT_EQ(e.at.y, 720);
  EXPECT_EQ(c.dropouts, 1u);
  e = c.update(300, {});
  EXPECT_DOUBLE_EQ(c.safe_ms, 139);
  e = c.update(310, {at(500, 500, 305)});
  EXPECT_EQ(e.state, gaze_state::tracking);
  EXPECT_EQ(e.at.x, 500);
  e = c.update(600, {});
  EXPECT_EQ(c.dropouts, 2u);
  // A replay is never dropped: its last sample stands.
  gaze_conditioner replay(p, fove, false);
  replay.update(0, {at(100, 200, 0)});
  e = replay.update(10000, {});
  EXPECT_EQ(e.state, gaze_state::tracking);
  EXPECT_EQ(e.at.x, 100);
}

TEST(GazeConditioning, RefusesParametersOutOfRange) {
  gaze_conditioning p;
  EXPECT_EQ(gaze_conditioning_problem(p), "");
  p.min_confidence = 1.5;
  EXPECT_EQ(gaze_conditioning_problem(p), "--gaze-min-confidence must lie in 0..1");
  p = {};
  p.beta = 0.1;
  EXPECT_EQ(gaze_conditioning_problem(p), "--gaze-filter: beta needs a minimum cutoff above 0");
  p = {};
  p.saccade_deg_s = -1;
  EXPECT_NE(gaze_conditioning_problem(p), "");
  p = {};
  p.hold_ms = NAN;
  EXPECT_NE(gaze_conditioning_problem(p), "");
}

}  // namespace
}  // namespace fov
