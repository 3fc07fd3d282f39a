#include <cmath>

#include <gtest/gtest.h>

#include <array>
#include <map>

#include "fov/acuity.h"
#include "fov/pointset.h"

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

// The headsets' presets give their source's pixels per degree at the centre, at their
// per-eye resolution; the thesis's presets keep v = 1 (their sets' names depend on it).
TEST(Display, PresetsGiveTheirPixelsPerDegree) {
  const std::map<std::string, double> ppd = {{"quest3", 25}, {"vision-pro", 34}, {"varjo-xr4", 51}, {"retinal", 70}};
  for (const auto& [name, want] : ppd) {
    display_geometry d;
    ASSERT_TRUE(display_preset(name, d)) << name;
    EXPECT_NEAR(pixels_per_degree(d), want, 1e-9) << name;
    EXPECT_EQ(display_name(d), name);
  }
  display_geometry fove;
  ASSERT_TRUE(display_preset("fove", fove));
  EXPECT_EQ(fove.viewing_distance, 1.0);
  EXPECT_NEAR(pixels_per_degree(fove), 1280 * 3.14159265358979 / 180, 1e-9);  // 22.3: the thesis's FOVE
  EXPECT_NEAR(horizontal_fov_deg(fove), 2 * std::atan(0.5) * 180 / 3.14159265358979, 1e-9);
  EXPECT_NEAR(vertical_fov_deg(fove), 2 * std::atan(0.5 * 1440 / 1280) * 180 / 3.14159265358979, 1e-9);
  // Every preset is a display every tool takes, named by its own name.
  for (const display_preset_info& p : display_presets()) {
    display_geometry d;
    EXPECT_EQ(parse_display(p.name, d), "") << p.name;
    EXPECT_EQ(display_name(d), p.name);
    EXPECT_EQ(viewing_distance_problem(d.viewing_distance), "") << p.name;
  }
}

TEST(Display, SpecsGiveTheGeometryTheySay) {
  display_geometry d;
  ASSERT_EQ(parse_display("640x720", d), "");
  EXPECT_EQ(d.width, 640);
  EXPECT_EQ(d.height, 720);
  EXPECT_EQ(d.viewing_distance, 1.0);
  ASSERT_EQ(parse_display("3840x3840@70ppd", d), "");
  EXPECT_EQ(d.width, 3840);
  EXPECT_EQ(d.height, 3840);
  EXPECT_NEAR(pixels_per_degree(d), 70, 1e-9);
  EXPECT_EQ(display_name(d), "retinal");  // the same geometry as the preset, so the same sets
  ASSERT_EQ(parse_display("2000x1000@90deg", d), "");
  EXPECT_NEAR(horizontal_fov_deg(d), 90, 1e-9);
  EXPECT_NEAR(d.viewing_distance, 0.5, 1e-12);
  ASSERT_EQ(parse_display("100x80@2.5", d), "");
  EXPECT_EQ(d.viewing_distance, 2.5);
  EXPECT_EQ(display_name(d), "100x80-v2.5");
  ASSERT_EQ(parse_display("1280x1440", d), "");
  EXPECT_EQ(display_name(d), "fove");
  // Refused, with the reason, and `out` untouched.
  const display_geometry before = d;
  for (const char* bad : {"", "oculus", "x", "640x", "x720", "640x720x2", "-640x720", "640 x 720", "640x720@", "640x720@ppd",
                          "640x720@-3ppd", "640x720@0", "640x720@1e3", "640x720@nan", "640x720@inf", "640x720@180deg",
                          "640x720@200deg", "640x720@2000", "640x720@0.001", "7x720", "640x8193", "99999999999x720",
                          "640x720@1ppdd", "640x720@@1"}) {
    const std::string why = parse_display(bad, d);
    EXPECT_NE(why, "") << bad;
    EXPECT_EQ(d.width, before.width) << bad;
    EXPECT_EQ(d.viewing_distance, before.viewing_distance) << bad;
  }
  EXPECT_NE(parse_display("oculus", d).find("quest3"), std::string::npos) << "the message lists the presets";
  EXPECT_NE(parse_display("7x720", d).find("8..8192"), std::string::npos);
  EXPECT_NE(parse_display("640x720@2000", d).find("1000"), std::string::npos) << "the distance's range";
}

TEST(Display, FileNamesComeFromOneFunction) {
  spacing_model m;
  ASSERT_TRUE(display_preset("fove", m.display));
  dart_params darts;
  EXPECT_EQ(pointset_file_name(m, darts), "fove-s1.00.fovset");
  m.scale = 1.75;
  darts.fovea = fovea_layout::grid;
  EXPECT_EQ(pointset_file_name(m, darts), "fove-s1.75-grid.fovset");
  darts.grid_spacing = 1.5;
  EXPECT_EQ(pointset_file_name(m, darts), "fove-s1.75-grid-1.50.fovset");
  ASSERT_EQ(parse_display("640x720", m.display), "");
  m.scale = 1.0;
  EXPECT_EQ(pointset_file_name(m, dart_params{}), "640x720-v1-s1.00.fovset");
  ASSERT_EQ(parse_display("3840x3840@60ppd", m.display), "");
  EXPECT_EQ(pointset_file_name(m, dart_params{}), "3840x3840-v0.8952-s1.00.fovset");
  // Two distances that differ are two names.
  display_geometry a{640, 720, 1.0}, b{640, 720, 1.1};
  EXPECT_NE(display_name(a), display_name(b));
}

// Issue 27: Guenter's linear MAR as HVVR samples it, one sample per MAR, so the cut-off is
// half the MAR's reciprocal: 30 cpd in the dead zone (w0 = 1/60 degree), and at 10.5 degrees
// w = 0.022 * 10 + 1/60 degrees. Spacing then follows Eq. 4 as for the CSF.
TEST(Acuity, LinearMarGivesGuentersCutoff) {
  acuity_params a;
  a.model = acuity_model::linear_mar;
  EXPECT_NEAR(cutoff_frequency_cpd(a, 0.0), 30.0, 1e-12);
  EXPECT_NEAR(cutoff_frequency_cpd(a, 0.5), 30.0, 1e-12);
  EXPECT_NEAR(cutoff_frequency_cpd(a, 10.5), 1 / (2 * (0.022 * 10 + 1.0 / 60)), 1e-12);  // 2.11 cpd
  a.mar_dead_zone_deg = 0, a.mar_slope = 0.0275, a.mar_fovea_deg = 1.0 / 48;             // Guenter's m_A, w0
  EXPECT_NEAR(cutoff_frequency_cpd(a, 20.0), 1 / (2 * (0.0275 * 20 + 1.0 / 48)), 1e-12);
  spacing_model m;  // FOVE, s = 1: at d = 1280 px, e = 45 degrees
  m.acuity.model = acuity_model::linear_mar;
  const double fd = display_nyquist_cpd(m.display), fc = 1 / (2 * (0.022 * 44.5 + 1.0 / 60));
  EXPECT_NEAR(point_spacing_px(m, 1280.0), fd / fc - (1 - std::sqrt(1 / pi)), 1e-9);  // 22.8 px
  EXPECT_NEAR(point_spacing_px(m, 0.0), std::sqrt(1 / pi), 1e-12);  // display-limited fovea
}

// VaFR's piecewise model: the acuities it gives at its pivots, the MAR (1/f) linear between
// them, and past 60 degrees the last segment's line continued.
TEST(Acuity, PiecewiseMarHitsItsPivotsAndIsLinearInMarBetween) {
  acuity_params a;
  a.model = acuity_model::piecewise_mar;
  const double want[5] = {40, 10, 6, 5, 4};
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(cutoff_frequency_cpd(a, piecewise_pivots_deg[i]), want[i], 1e-9) << i;
  EXPECT_NEAR(cutoff_frequency_cpd(a, 5.0), 1 / (0.5 * (1.0 / 40 + 1.0 / 10)), 1e-12);  // 16 cpd
  EXPECT_NEAR(cutoff_frequency_cpd(a, 15.0), 1 / (0.5 * (1.0 / 10 + 1.0 / 6)), 1e-12);  // 7.5 cpd
  EXPECT_NEAR(cutoff_frequency_cpd(a, 45.0), 1 / (0.5 * (1.0 / 5 + 1.0 / 4)), 1e-12);
  EXPECT_NEAR(cutoff_frequency_cpd(a, 90.0), 1 / (0.25 + 30 * (0.25 - 0.2) / 30), 1e-12);  // extrapolated: 3.33 cpd
  // Continuous at the pivots from both sides.
  for (int i = 1; i < 5; ++i)
    EXPECT_NEAR(cutoff_frequency_cpd(a, piecewise_pivots_deg[i] - 1e-9), cutoff_frequency_cpd(a, piecewise_pivots_deg[i]),
                1e-6);
}

TEST(Acuity, EveryModelsSpacingNeverShrinksWithDistance) {
  for (const auto& [label, model] : acuity_model_labels)
    for (double s : {0.5, 1.0, 3.0})
      for (double v : {0.05, 1.0, 50.0}) {
        spacing_model m;
        m.acuity.model = model;
        m.scale = s;
        m.display.viewing_distance = v;
        double previous = 0;
        for (int i = 0; i <= 4000; ++i) {
          const double p = point_spacing_px(m, i);
          ASSERT_TRUE(std::isfinite(p) && p > 0) << label;
          ASSERT_GE(p, previous) << label << " s=" << s << " v=" << v << " d=" << i;
          previous = p;
        }
      }
}

TEST(Acuity, ModelParametersOutsideTheirRangesAreNamed) {
  auto why = [](auto&& edit) {
    spacing_model m;
    edit(m.acuity);
    return validate(m);
  };
  auto linear = [](double m, double w0, double dz) {
    return [=](acuity_params& a) { a.model = acuity_model::linear_mar, a.mar_slope = m, a.mar_fovea_deg = w0, a.mar_dead_zone_deg = dz; };
  };
  EXPECT_EQ(why(linear(0.022, 1.0 / 60, 0.5)), "");
  EXPECT_NE(why(linear(0, 1.0 / 60, 0.5)).find("MAR slope"), std::string::npos);
  EXPECT_NE(why(linear(1.5, 1.0 / 60, 0.5)).find("MAR slope"), std::string::npos);
  EXPECT_NE(why(linear(NAN, 1.0 / 60, 0.5)).find("MAR slope"), std::string::npos);
  EXPECT_NE(why(linear(0.022, 0, 0.5)).find("foveal MAR"), std::string::npos);
  EXPECT_NE(why(linear(0.022, INFINITY, 0.5)).find("foveal MAR"), std::string::npos);
  EXPECT_NE(why(linear(0.022, 1.0 / 60, -1)).find("dead zone"), std::string::npos);
  EXPECT_NE(why(linear(0.022, 1.0 / 60, 31)).find("dead zone"), std::string::npos);
  auto piecewise = [](std::array<double, 5> f) {
    return [=](acuity_params& a) {
      a.model = acuity_model::piecewise_mar;
      std::copy(f.begin(), f.end(), a.pivot_cpd);
    };
  };
  EXPECT_EQ(why(piecewise({40, 10, 6, 5, 4})), "");
  EXPECT_EQ(why(piecewise({9, 9, 9, 9, 9})), "");  // constant acuity: allowed
  EXPECT_NE(why(piecewise({40, 10, 12, 5, 4})).find("must not grow"), std::string::npos);
  EXPECT_NE(why(piecewise({40, 10, 6, 5, 0})).find("at 60 degrees"), std::string::npos);
  EXPECT_NE(why(piecewise({400, 10, 6, 5, 4})).find("at 0 degrees"), std::string::npos);
  EXPECT_NE(why(piecewise({40, NAN, 6, 5, 4})).find("at 10 degrees"), std::string::npos);
}

TEST(Display, FileNamesCarryTheAcuityModelAndItsParameters) {
  spacing_model m;
  ASSERT_TRUE(display_preset("fove", m.display));
  m.acuity.model = acuity_model::linear_mar;
  EXPECT_EQ(pointset_file_name(m, dart_params{}), "fove-linear-mar-s1.00.fovset");
  m.acuity.mar_slope = 0.0275;
  EXPECT_EQ(pointset_file_name(m, dart_params{}), "fove-linear-mar-m0.0275-w0.01667-d0.5-s1.00.fovset");
  m.acuity = {};
  m.acuity.model = acuity_model::piecewise_mar;
  EXPECT_EQ(pointset_file_name(m, dart_params{}, {3.0, 1.0}), "fove-piecewise-mar-n1.00-3.00.fovset");
  m.acuity.pivot_cpd[1] = 12;
  EXPECT_EQ(pointset_file_name(m, dart_params{}), "fove-piecewise-mar-f40-12-6-5-4-s1.00.fovset");
  // Parameters of another model do not change a name (nor the spacing).
  m.acuity = {};
  m.acuity.mar_slope = 0.5;
  EXPECT_EQ(pointset_file_name(m, dart_params{}), "fove-s1.00.fovset");
  EXPECT_TRUE(same_acuity(m.acuity, acuity_params{}));
}

}  // namespace
}  // namespace fov
