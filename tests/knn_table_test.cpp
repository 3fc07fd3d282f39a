#include <cmath>
#include <algorithm>
#include <random>
#include <set>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "fov/knn_table.h"
#include "test_sets.h"

namespace fov {
namespace {

using testing::quick_darts;
using testing::small_model;

// A table with this shape and no entries: enough for offset arithmetic.
knn_table shape(uint32_t width, uint32_t height, uint32_t k, uint32_t group) {
  knn_table t;
  t.width = width;
  t.height = height;
  t.k = k;
  t.group = group;
  return t;
}

TEST(KnnTable, EqualsBruteForceAtEveryPixel) {
  for (auto [w, h, s, k] : {std::tuple{48, 40, 1.0, 20u}, {40, 32, 3.0, 32u}, {36, 30, 1.0, 1u}, {30, 40, 2.0, 5u}}) {
    const std::vector<point> pts = throw_darts(small_model(w, h, 1.0, s), quick_darts());
    knn_params kp;
    kp.k = k;
    const knn_table t = build_knn_table(pts, 2 * w, 2 * h, kp);
    for (uint32_t y = 0; y < t.height; ++y)
      for (uint32_t x = 0; x < t.width; ++x) {
        const std::vector<uint32_t> expected = brute_force_knn(pts, x + 0.5f, y + 0.5f, k);
        for (uint32_t j = 0; j < k; ++j)
          ASSERT_EQ(t.at(x, y, j), expected[j]) << "pixel " << x << "," << y << " rank " << j << " k=" << k;
      }
  }
}

TEST(KnnTable, TiesGoToTheSmallerIndex) {
  // A regular lattice puts many points at exactly equal distances from pixel centres.
  std::vector<point> pts;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) pts.push_back({2.0f * x + 1.0f, 2.0f * y + 1.0f, 1.0f});
  knn_params kp;
  kp.k = 8;
  const knn_table t = build_knn_table(pts, 16, 16, kp);
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 16; ++x) {
      const auto expected = brute_force_knn(pts, x + 0.5f, y + 0.5f, 8);
      for (uint32_t j = 0; j < 8; ++j) ASSERT_EQ(t.at(x, y, j), expected[j]) << x << "," << y << " rank " << j;
    }
  // Pixel (0,0) centre (0.5,0.5): nearest (1,1) = index 0; then (3,1) idx 1 and (1,3) idx 8 tie at sqrt(6.5).
  EXPECT_EQ(t.at(0, 0, 0), 0u);
  EXPECT_EQ(t.at(0, 0, 1), 1u);
  EXPECT_EQ(t.at(0, 0, 2), 8u);
}

TEST(KnnTable, GroupedLayoutIsABijectionForEveryGroupSize) {
  for (uint32_t k : {1u, 5u, 7u, 20u, 32u})
    for (uint32_t g : {1u, 3u, 4u, 8u, 32u}) {
      const knn_table t = shape(5, 3, k, std::min(g, k));
      std::vector<int> hit(t.pixel_count() * k, 0);
      for (uint64_t p = 0; p < t.pixel_count(); ++p)
        for (uint32_t j = 0; j < k; ++j) {
          const uint64_t o = t.offset(p, j);
          ASSERT_LT(o, hit.size());
          ++hit[o];
        }
      for (int v : hit) ASSERT_EQ(v, 1) << "k=" << k << " group=" << g;
    }
}

TEST(KnnTable, FirstRanksOfAGroupArePlanarPerPixel) {
  // group = 4: ranks 0..3 of pixel p are contiguous, and pixel p+1 follows them.
  const knn_table t = shape(10, 10, 20, 4);
  EXPECT_EQ(t.offset(0, 0), 0u);
  EXPECT_EQ(t.offset(0, 3), 3u);
  EXPECT_EQ(t.offset(1, 0), 4u);
  EXPECT_EQ(t.offset(0, 4), 400u);  // the second group starts after 100 pixels x 4 ranks
}

TEST(KnnTable, EightKOffsetsDoNotOverflow) {
  // An 8K screen's canvas has 15360 x 8640 x 20 = 2.65e9 entries, past 2^31 and 2^32 / 2.
  knn_table t = shape(15360, 8640, 20, 4);
  const uint64_t last = t.pixel_count() - 1;
  EXPECT_EQ(t.offset(last, 19), t.pixel_count() * 20 - 1);
  EXPECT_GT(t.offset(last, 19), uint64_t(1) << 31);
  t.group = 1;
  EXPECT_EQ(t.offset(last, 19), t.pixel_count() * 20 - 1);
}

TEST(KnnTable, RegroupKeepsEveryEntry) {
  const std::vector<point> pts = throw_darts(small_model(40, 30), quick_darts());
  knn_params kp;
  kp.k = 10;
  kp.group = 10;
  const knn_table a = build_knn_table(pts, 80, 60, kp);
  for (uint32_t g : {1u, 3u, 4u}) {
    const knn_table b = regroup(a, g);
    EXPECT_EQ(b.group, g);
    for (uint32_t y = 0; y < 60; ++y)
      for (uint32_t x = 0; x < 80; ++x)
        for (uint32_t j = 0; j < 10; ++j) ASSERT_EQ(a.at(x, y, j), b.at(x, y, j));
  }
}

TEST(KnnTable, SameTableForAnyThreadCount) {
  const std::vector<point> pts = throw_darts(small_model(64, 64), quick_darts());
  knn_table one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = build_knn_table(pts, 128, 128, {});
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = build_knn_table(pts, 128, 128, {});
  }
  EXPECT_EQ(one.entries, two.entries);
}

TEST(KnnTable, RejectsKOutsideRangeOrAboveThePointCount) {
  const std::vector<point> pts = throw_darts(small_model(1, 1), quick_darts());
  ASSERT_LT(pts.size(), 20u);  // a 1x1 screen has a 2x2 canvas with a handful of points
  knn_params kp;
  try {
    build_knn_table(pts, 2, 2, kp);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the"), std::string::npos);
  }
  kp.k = uint32_t(pts.size());
  const knn_table t = build_knn_table(pts, 2, 2, kp);  // the 1x1 screen works with k <= points
  EXPECT_EQ(t.entries.size(), 4u * pts.size());
  kp.k = 0;
  EXPECT_THROW(build_knn_table(pts, 2, 2, kp), std::invalid_argument);
  kp.k = 33;
  EXPECT_THROW(build_knn_table(pts, 2, 2, kp), std::invalid_argument);
}

TEST(TracedPoints, EveryPixelReadsOnlyTracedPoints) {
  const int w = 96, h = 80;
  pointset set;
  set.model = small_model(w, h);
  set.points = throw_darts(set.model, quick_darts());
  set.table = build_knn_table(set.points, 2 * w, 2 * h, {});
  // Per-rank radii: non-decreasing, the last is max_radius.
  ASSERT_EQ(set.table.radius_by_rank.size(), 20u);
  for (size_t j = 1; j < 20; ++j) EXPECT_LE(set.table.radius_by_rank[j - 1], set.table.radius_by_rank[j]);
  EXPECT_EQ(set.table.radius_by_rank.back(), set.table.max_radius);
  for (uint32_t k_used : {1u, 5u, 20u})
  for (auto [gx, gy] : {std::pair{48.0, 40.0}, {0.0, 0.0}, {96.0, 80.0}, {10.4, 70.6}}) {
    const std::vector<uint8_t> mask = traced_point_mask(set, {gx, gy}, k_used);
    const canvas_offset o = offset_for_gaze(set.model.display, {gx, gy});
    std::set<uint32_t> needed;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (uint32_t j = 0; j < k_used; ++j) needed.insert(set.table.at(x + o.x, y + o.y, j));
    uint64_t on_screen = 0, off = 0;
    for (uint32_t i = 0; i < set.points.size(); ++i) {
      const point& p = set.points[i];
      const bool on = p.x >= o.x && p.x < o.x + w && p.y >= o.y && p.y < o.y + h;
      ASSERT_EQ(bool(mask[i]), on || needed.count(i)) << "point " << i << ", k_used " << k_used;
      on_screen += on;
      off += !on && needed.count(i);
    }
    const traced_set t = count_traced_points(set, {gx, gy}, k_used);
    EXPECT_EQ(t.on_screen, on_screen);
    EXPECT_EQ(t.referenced_off_screen, off);
    if (k_used > 1) {
      EXPECT_GT(off, 0u) << "some off-screen points must be read near the screen edge";
    }
  }
}

TEST(TracedPoints, TheListIsTheMaskInOrder) {
  // Big enough for several of traced_points' compaction blocks (16384 points each).
  const int w = 320, h = 240;
  pointset set;
  set.model = small_model(w, h, 1.0, 0.6);
  set.points = throw_darts(set.model, quick_darts());
  ASSERT_GT(set.points.size(), 3u * 16384) << "the set must span several blocks";
  knn_params kp;
  kp.k = 5;
  set.table = build_knn_table(set.points, 2 * w, 2 * h, kp);
  for (auto [gx, gy] : {std::pair{160.0, 120.0}, {0.0, 240.0}}) {
    const std::vector<uint8_t> mask = traced_point_mask(set, {gx, gy}, 5);
    std::vector<uint32_t> expected;
    for (uint32_t i = 0; i < mask.size(); ++i)
      if (mask[i]) expected.push_back(i);
    EXPECT_EQ(traced_points(set, {gx, gy}, 5), expected);
  }
}

// The index (make_traced_index) finds the same list as the table scan, for every k, at
// gazes that put each screen corner and edge in the canvas's dense centre and its sparse
// border, and at random gazes; on one and two threads.
TEST(TracedPoints, TheIndexFindsTheSameListAsTheScan) {
  const int w = 160, h = 120;
  pointset set;
  set.model = small_model(w, h, 1.0, 0.8);
  set.points = throw_darts(set.model, quick_darts());
  set.table = build_knn_table(set.points, 2 * w, 2 * h, {});
  std::vector<std::pair<double, double>> gazes = {{80, 60}, {0, 0}, {160, 120}, {0, 120}, {160, 0}, {80, 0}, {0, 60}, {3.5, 117.2}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> gx(-10, w + 10), gy(-10, h + 10);
  for (int i = 0; i < 40; ++i) gazes.emplace_back(gx(rng), gy(rng));
  for (uint32_t k_used : {1u, 2u, 5u, 20u}) {
    const traced_index index = make_traced_index(set, k_used);
    ASSERT_TRUE(index.morton);
    ASSERT_EQ(index.reaches.size(), set.points.size());
    EXPECT_GE(float(index.margin), set.table.radius_by_rank[k_used - 1]) << "k_used " << k_used;
    for (auto [x, y] : gazes) {
      const std::vector<uint32_t> scanned = traced_points(set, {x, y}, k_used);
      ASSERT_EQ(traced_points(set, index, {x, y}), scanned) << "k_used " << k_used << ", gaze " << x << ", " << y;
    }
  }
  const traced_index index = make_traced_index(set, 5);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const traced_index serial = make_traced_index(set, 5);
  for (size_t i = 0; i < set.points.size(); ++i) {
    ASSERT_EQ(serial.reaches[i].min_x, index.reaches[i].min_x);
    ASSERT_EQ(serial.reaches[i].max_y, index.reaches[i].max_y);
  }
}

// A table whose ranks are not nearest first (a hand-made or imported set; the fuzzer made
// one: a far point at rank 0) still gives every point an on-screen pixel reads: the scan's border comes from the
// radii over the first k ranks, not the k-th alone. Checked against reading every pixel.
TEST(TracedPoints, ATableOutOfNearestFirstOrderStillGivesEveryPointRead) {
  const int w = 64, h = 48;
  pointset set;
  set.model = small_model(w, h);
  set.points = throw_darts(set.model, quick_darts());
  set.table = build_knn_table(set.points, 2 * w, 2 * h, {});
  knn_table& t = set.table;
  for (uint32_t y = 0; y < t.height; ++y)  // farthest first
    for (uint32_t x = 0; x < t.width; ++x)
      for (uint32_t j = 0; j < t.k / 2; ++j) {
        const uint64_t pixel = uint64_t(y) * t.width + x;
        std::swap(t.entries[t.offset(pixel, j)], t.entries[t.offset(pixel, t.k - 1 - j)]);
      }
  // ... and a pixel in the middle of the canvas whose nearest rank is the point farthest from it.
  uint32_t far = 0;
  for (uint32_t i = 0; i < set.points.size(); ++i)
    if (set.points[i].x + set.points[i].y < set.points[far].x + set.points[far].y) far = i;
  t.entries[t.offset(uint64_t(h) * t.width + w, 0)] = far;
  set_knn_radii(t, set.points);
  for (uint32_t k_used : {1u, 3u, t.k}) {
    const traced_index index = make_traced_index(set, k_used);
    for (auto [gx, gy] : std::vector<std::pair<double, double>>{{32, 24}, {0, 0}, {64, 48}, {5, 40}}) {
      const canvas_offset o = offset_for_gaze(set.model.display, {gx, gy});
      std::set<uint32_t> read;
      for (uint32_t i = 0; i < set.points.size(); ++i)
        if (on_screen(set.points[i], set.model.display, o)) read.insert(i);
      for (int y = o.y; y < o.y + h; ++y)
        for (int x = o.x; x < o.x + w; ++x)
          for (uint32_t j = 0; j < k_used; ++j) read.insert(t.at(uint32_t(x), uint32_t(y), j));
      const std::vector<uint32_t> every(read.begin(), read.end());
      ASSERT_EQ(traced_points(set, {gx, gy}, k_used), every) << "scan, k_used " << k_used << ", gaze " << gx << ", " << gy;
      ASSERT_EQ(traced_points(set, index, {gx, gy}), every) << "index, k_used " << k_used << ", gaze " << gx << ", " << gy;
    }
  }
}

// Points out of Morton order (a hand-made set) still give the right list: the index
// says so and traced_points falls back to the scan. A k beyond the table's is clamped,
// as the scan clamps it; an index of another set or k is refused.
TEST(TracedPoints, TheIndexFallsBackAndRefusesAnotherSet) {
  const int w = 64, h = 48;
  pointset set;
  set.model = small_model(w, h);
  set.points = throw_darts(set.model, quick_darts());
  std::reverse(set.points.begin(), set.points.end());
  set.table = build_knn_table(set.points, 2 * w, 2 * h, {});
  const traced_index index = make_traced_index(set, 5);
  EXPECT_FALSE(index.morton);
  EXPECT_EQ(traced_points(set, index, {10, 40}), traced_points(set, {10, 40}, 5));
  EXPECT_EQ(make_traced_index(set, 99).k_used, set.table.k);
  EXPECT_THROW(make_traced_index(set, 0), std::invalid_argument);
  pointset other = set;
  other.points.pop_back();
  EXPECT_THROW(traced_points(other, index, {10, 40}), std::invalid_argument);
}

TEST(TracedPoints, ASetWithoutItsTableIsRefused) {
  pointset set;
  set.model.display = {32, 24, 1.0};
  set.points = throw_darts(set.model, quick_darts());
  try {
    count_traced_points(set, {16, 12}, 20);
    FAIL() << "no table, yet counted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("table is not loaded"), std::string::npos);
  }
  set.table = build_knn_table(set.points, 64, 48, {});
  EXPECT_NO_THROW(count_traced_points(set, {16, 12}, 20));
  set.table.entries.clear();  // the shape of a header-only load
  EXPECT_THROW(traced_point_mask(set, {16, 12}, 20), std::invalid_argument);
}

TEST(TracedPoints, GazeShiftRoundsHalfUpAndClamps) {
  const display_geometry d{100, 50, 1.0};
  EXPECT_EQ(offset_for_gaze(d, {50, 25}).x, 50);
  EXPECT_EQ(offset_for_gaze(d, {10.5, 0}).x, 89);  // round(10.5) = 11
  EXPECT_EQ(offset_for_gaze(d, {10.49, 0}).x, 90);
  EXPECT_EQ(offset_for_gaze(d, {-20, 0}).x, 100);  // clamped to the screen
  EXPECT_EQ(offset_for_gaze(d, {500, 0}).x, 0);
  EXPECT_EQ(offset_for_gaze(d, {0, 1e9}).y, 0);
  EXPECT_EQ(offset_for_gaze(d, {NAN, NAN}).x, 50);  // no gaze: centre
}

}  // namespace
}  // namespace fov

namespace fov {
namespace {

// The uniform baseline: the asked fraction of the pixels on every screen placement, at
// the stated spacing, with a table like any set's.
TEST(UniformSet, HoldsItsFractionAtItsSpacing) {
  const display_geometry d{16, 12, 1.0};
  knn_params kp;
  kp.k = 4;
  for (double fraction : {0.5, 0.25, 0.125}) {
    const pointset set = uniform_pointset(d, fraction, kp);
    EXPECT_EQ(set.points.size(), size_t(std::lround(4 * 16 * 12 * fraction))) << fraction;
    for (const gaze_point g : {gaze_point{8, 6}, gaze_point{3, 9}, gaze_point{0, 0}}) {
      const canvas_offset o = offset_for_gaze(d, g);
      size_t on = 0;
      for (const point& p : set.points) on += on_screen(p, d, o);
      EXPECT_EQ(on, size_t(std::lround(16 * 12 * fraction))) << fraction;
    }
    const double pitch = fraction == 0.5 ? std::sqrt(2.0) : fraction == 0.25 ? 2.0 : 2 * std::sqrt(2.0);
    for (size_t i = 0; i < set.points.size(); i += 7) {
      const std::vector<uint32_t> nn = brute_force_knn(set.points, set.points[i].x, set.points[i].y, 2);
      const point& q = set.points[nn[1]];
      EXPECT_NEAR(std::hypot(q.x - set.points[i].x, q.y - set.points[i].y), pitch, 1e-5);
      EXPECT_FLOAT_EQ(set.points[i].spacing, float(pitch));
    }
    EXPECT_EQ(set.table.width, 32u);
    EXPECT_EQ(set.table.k, 4u);
  }
  EXPECT_THROW(uniform_pointset(d, 0.3, kp), std::invalid_argument);
  EXPECT_THROW(uniform_pointset(d, 1.0, kp), std::invalid_argument);
}

}  // namespace
}  // namespace fov
