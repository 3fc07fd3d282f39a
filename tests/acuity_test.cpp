#include <cmath>

#include <gtest/gtest.h>

#include "fov/acuity.h"

namespace fov {
namespace {

constexpr double pi = 3.14159265358979323846;

TEST(Acuity, ThesisEquationsAtTheFoveCentre) {
  spacing_model m;  // FOVE 1280x1440, v = 1, s = 1
  EXPECT_NEAR(display_nyquist_cpd(m.display), pi * 1280 / 360, 1e-12);  // Eq. 3: 11.17 cpd
  EXPECT_NEAR(cutoff_frequency_cpd(m.acuity, 0.0), std::log(64.0) / 0.106, 1e-9);  // Eq. 2 at e = 0: 39.2 cpd
  // Eq. 4 in the display-limited fovea: p = 1 - (1 - sqrt(1/pi)) = 0.5642 px.
  EXPECT_NEAR(point_spacing_px(m, 0.0), std::sqrt(1 / pi), 1e-12);
  EXPECT_NEAR(point_spacing_px(m, 100.0), std::sqrt(1 / pi), 1e-12);
}

TEST(Acuity, EccentricityScalesLinearlyWithS) {
  spacing_model m;
  const double e1 = eccentricity_deg(m, 640.0);
  EXPECT_NEAR(e1, std::atan(0.5) * 180 / pi, 1e-12);  // Eq. 1: 26.57 degrees at half a display width
  m.scale = 1.75;
  EXPECT_NEAR(eccentricity_deg(m, 640.0), 1.75 * e1, 1e-12);
}

TEST(Acuity, SpacingLeavesTheFoveaWhereCutoffMeetsNyquist) {
  spacing_model m;
  // fc = fd at e = e2 ln(1/CT0) / (alpha fd) - e2 = 5.78 degrees, i.e. d = 1280 tan(5.78 deg) = 129.6 px.
  const double fd = display_nyquist_cpd(m.display);
  const double e_star = 2.3 * std::log(64.0) / (0.106 * fd) - 2.3;
  const double d_star = 1280 * std::tan(e_star * pi / 180);
  EXPECT_NEAR(point_spacing_px(m, d_star - 1), std::sqrt(1 / pi), 1e-12);
  EXPECT_GT(point_spacing_px(m, d_star + 1), std::sqrt(1 / pi) + 1e-4);
  // At the canvas corner (d = 1926 px, e = 56.4 deg): p = fd / fc - (1 - a) = 6.83 px.
  const double d = std::hypot(1280.0, 1440.0);
  const double e = std::atan(d / 1280) * 180 / pi;
  const double fc = 2.3 * std::log(64.0) / ((e + 2.3) * 0.106);
  EXPECT_NEAR(point_spacing_px(m, d), fd / fc - (1 - std::sqrt(1 / pi)), 1e-9);
  EXPECT_NEAR(point_spacing_px(m, d), 6.83, 0.01);
}

TEST(Acuity, SpacingNeverShrinksWithDistance) {
  for (double s : {0.5, 1.0, 1.75, 3.0, 10.0})
    for (double v : {0.05, 1.0, 50.0}) {
      spacing_model m;
      m.scale = s;
      m.display.viewing_distance = v;
      double previous = 0;
      for (int i = 0; i <= 4000; ++i) {
        const double p = point_spacing_px(m, i);
        ASSERT_TRUE(std::isfinite(p));
        ASSERT_GE(p, previous) << "s=" << s << " v=" << v << " d=" << i;
        previous = p;
      }
    }
}

TEST(Acuity, ValidateNamesTheBadParameter) {
  spacing_model m;
  EXPECT_EQ(validate(m), "");
  m.display.width = 0;
  EXPECT_NE(validate(m).find("width"), std::string::npos);
  m = {};
  m.display.height = -3;
  EXPECT_NE(validate(m).find("height"), std::string::npos);
  m = {};
  m.display.viewing_distance = 0;
  EXPECT_NE(validate(m).find("viewing distance"), std::string::npos);
  m.display.viewing_distance = NAN;
  EXPECT_NE(validate(m).find("viewing distance"), std::string::npos);
  m = {};
  m.scale = -1;
  EXPECT_NE(validate(m).find("scale"), std::string::npos);
  m = {};
  m.acuity.model = acuity_model(99);
  EXPECT_NE(validate(m).find("acuity model"), std::string::npos);
}

TEST(Acuity, ExtremeDisplaysGiveFiniteSpacing) {
  for (auto [w, h] : {std::pair{1, 1}, {7680, 4320}, {65536, 65536}}) {
    spacing_model m;
    m.display.width = w;
    m.display.height = h;
    EXPECT_EQ(validate(m), "") << w << "x" << h;
    const double p = point_spacing_px(m, std::hypot(double(w), double(h)));
    EXPECT_TRUE(std::isfinite(p) && p > 0);
  }
  spacing_model huge;
  huge.display.width = 70000;
  EXPECT_NE(validate(huge), "");
}

TEST(Acuity, PresetsAreTheDocumentedDisplays) {
  display_geometry d;
  ASSERT_TRUE(display_preset("fove", d));
  EXPECT_EQ(d.width, 1280);
  EXPECT_EQ(d.height, 1440);
  ASSERT_TRUE(display_preset("vive", d));
  EXPECT_EQ(d.width, 1080);
  ASSERT_TRUE(display_preset("desktop1080", d));
  EXPECT_EQ(d.height, 1080);
  EXPECT_FALSE(display_preset("oculus", d));
}

}  // namespace
}  // namespace fov
