// Ring lattices (fovgen --sampler polar|log-polar; issue 27): rings a pitch apart, each ring's
// samples a pitch apart, the pitch the acuity model's, points on the canvas in Morton order.
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "fov/lattice.h"
#include "fov/pointset_io.h"
#include "test_sets.h"

namespace fov {
namespace {

constexpr double pi = 3.14159265358979323846;

spacing_model fove(acuity_model model = acuity_model::wang_csf) {
  spacing_model m;  // 1280 x 1440 seen from one width
  m.acuity.model = model;
  return m;
}

TEST(Lattice, PitchIsTheNyquistPitchOfTheCutoff) {
  const spacing_model m = fove();
  EXPECT_DOUBLE_EQ(lattice_pitch_px(m, 0), 1.0);  // the display limits the fovea: one pixel
  for (double d : {200.0, 640.0, 1900.0}) {
    const double fc = cutoff_frequency_cpd(m.acuity, eccentricity_deg(m, d));
    EXPECT_NEAR(lattice_pitch_px(m, d), display_nyquist_cpd(m.display) / fc, 1e-12) << d;
    // Eq. 4's dart spacing is the pitch less the thesis's offset.
    EXPECT_NEAR(point_spacing_px(m, d), lattice_pitch_px(m, d) - (1 - std::sqrt(1 / pi)), 1e-12) << d;
  }
}

// Polar rings step one pitch (the inner ring's) at a time; log-polar rings lie one unit of
// u = the integral of dr / q apart, so each gap's mean inverse pitch is 1 / gap (checked by a
// finer sum than the sampler's). Both reach past the canvas corner.
TEST(Lattice, RingsLieAPitchApart) {
  for (acuity_model model : {acuity_model::wang_csf, acuity_model::linear_mar, acuity_model::piecewise_mar}) {
    const spacing_model m = fove(model);
    const double corner = std::hypot(1280.0, 1440.0);
    const std::vector<double> polar = lattice_rings(m, point_sampler::polar);
    ASSERT_GT(polar.size(), 10u);
    EXPECT_DOUBLE_EQ(polar[0], lattice_pitch_px(m, 0));
    for (size_t j = 1; j < polar.size(); ++j)
      ASSERT_NEAR(polar[j] - polar[j - 1], lattice_pitch_px(m, polar[j - 1]), 1e-9) << j;
    EXPECT_GT(polar.back(), corner);
    EXPECT_LE(polar[polar.size() - 2], corner);
    const std::vector<double> lp = lattice_rings(m, point_sampler::log_polar);
    double previous = 0;
    for (size_t j = 0; j < lp.size(); j += 7) {
      const double a = j == 0 ? 0 : lp[j - 1], b = lp[j];
      double u = 0;
      for (int i = 0; i < 2000; ++i) u += (b - a) / 2000 / lattice_pitch_px(m, a + (b - a) * (i + 0.5) / 2000);
      ASSERT_NEAR(u, 1.0, 1e-4) << acuity_model_name(model) << " ring " << j;
      ASSERT_GT(b, previous);
      previous = b;
    }
    EXPECT_GT(lp.back(), corner);
  }
}

// Every ring's samples are at most a pitch apart along the ring and at least 6/7 of one (the
// first ring holds 7), and the counts add up: the set is the centre plus every ring's samples
// that fall on the canvas.
TEST(Lattice, RingSamplesLieAPitchApartAndTheSetHoldsThem) {
  const spacing_model m = testing::small_model(120, 90);
  for (point_sampler s : {point_sampler::polar, point_sampler::log_polar}) {
    uint64_t on_canvas = 1;
    for (double r : lattice_rings(m, s)) {
      const uint32_t n = lattice_ring_count(m, r);
      const double chord = 2 * r * std::sin(pi / n), q = lattice_pitch_px(m, r);
      EXPECT_LE(chord, q * (1 + 1e-9)) << r;
      EXPECT_GE(chord, q * 6 / 7 * 0.99) << r;
      // The samples on the canvas, counted as lattice_points places them.
      for (uint32_t i = 0; i < n; ++i) {
        const double a = s == point_sampler::polar ? (i + 0.5) * 2 * pi / n : i * q / r;
        const float x = float(120 + r * std::cos(a)), y = float(90 + r * std::sin(a));
        on_canvas += x >= 0 && y >= 0 && x < 240.f && y < 180.f;
      }
    }
    const std::vector<point> points = lattice_points(m, s);
    EXPECT_EQ(points.size(), on_canvas);
    for (size_t i = 1; i < points.size(); ++i)
      ASSERT_LE(morton_code(points[i - 1].x, points[i - 1].y), morton_code(points[i].x, points[i].y));
    // Each point's spacing is the pitch at its distance (its ring's radius, to float rounding).
    for (const point& p : points) {
      const double d = std::hypot(p.x - 120.0, p.y - 90.0);
      ASSERT_NEAR(p.spacing, lattice_pitch_px(m, d), 1e-3 * p.spacing);
    }
    EXPECT_EQ(lattice_points(m, s).size(), points.size());  // no randomness
  }
}

// The lattice samples the density the model asks for: in each annulus the number of points is
// the annulus's area over the squared pitch, within 15 % (rings of whole samples); and it is
// the same number of points whatever the seed.
TEST(Lattice, PointsPerAnnulusFollowThePitch) {
  const spacing_model m = fove(acuity_model::linear_mar);
  for (point_sampler s : {point_sampler::polar, point_sampler::log_polar}) {
    const std::vector<point> points = lattice_points(m, s);
    std::map<int, uint64_t> per_band;
    for (const point& p : points) {
      const double d = std::hypot(p.x - 1280.0, p.y - 1440.0);
      if (d < 1200) ++per_band[int(d / 200)];
    }
    for (int b = 0; b < 6; ++b) {
      double expected = 0;  // the integral of 2 pi r / q(r)^2 over the band
      for (int i = 0; i < 1000; ++i) {
        const double r = 200 * b + 0.2 * (i + 0.5);
        expected += 2 * pi * r * 0.2 / std::pow(lattice_pitch_px(m, r), 2);
      }
      EXPECT_NEAR(double(per_band[b]) / expected, 1.0, 0.15) << label_of(point_sampler_labels, s) << " band " << b;
    }
  }
}

// A lattice set goes through the whole chain: its neighbours (table and cells agree), its file
// (version 4, the sampler kept), and the loader refuses what no generator writes.
TEST(Lattice, SetsRoundTripWithTheirSampler) {
  const spacing_model m = testing::small_model(60, 50);
  for (point_sampler s : {point_sampler::polar, point_sampler::log_polar}) {
    dart_params d = testing::quick_darts();
    d.sampler = s;
    const testing::table_and_cells both = testing::both_ways(m, d, 6);
    uint32_t got[max_knn];
    for (uint32_t y = 0; y < both.table.table.height; y += 3)
      for (uint32_t x = 0; x < both.table.table.width; x += 3) {
        pixel_neighbours(both.cells, x, y, 6, got);
        for (uint32_t j = 0; j < 6; ++j) ASSERT_EQ(got[j], both.table.table.at(x, y, j));
      }
    const std::string path = ::testing::TempDir() + "/lattice-" + label_of(point_sampler_labels, s) + ".fovset";
    save_pointset(path, both.table);
    const pointset back = load_pointset(path);
    EXPECT_EQ(back.darts.sampler, s);
    EXPECT_EQ(back.points.size(), both.table.points.size());
    EXPECT_EQ(pointset_file_name(back.model, back.darts), std::string("60x50-v1-") + label_of(point_sampler_labels, s) + "-s1.00.fovset");
    std::remove(path.c_str());
  }
  dart_params grid = testing::grid_darts();
  grid.sampler = point_sampler::polar;
  EXPECT_THROW(place_points(m, grid, nullptr), std::invalid_argument);
  dart_params polar;
  polar.sampler = point_sampler::polar;
  EXPECT_THROW(throw_nested_pointset(m, {1.0, 2.0}, polar), std::invalid_argument);
}

}  // namespace
}  // namespace fov
