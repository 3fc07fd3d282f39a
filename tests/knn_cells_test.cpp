#include <algorithm>
#include <tuple>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "fov/knn_cells.h"
#include "fov/knn_table.h"
#include "test_sets.h"

namespace fov {
namespace {

using testing::grid_darts;
using testing::partial_grid_model;
using testing::quick_darts;
using testing::small_model;

// Every pixel's first k' neighbours from the cells equal the exact table's, for every k'.
void expect_cells_equal_table(const std::vector<point>& pts, uint32_t w, uint32_t h, uint32_t k, double fraction) {
  knn_params kp;
  kp.k = k;
  const knn_table t = build_knn_table(pts, w, h, kp);
  knn_cells_params cp;
  cp.k = k;
  cp.cell_fraction = fraction;
  const knn_cells c = build_knn_cells(pts, w, h, cp);
  ASSERT_EQ(knn_cells_problem(c, pts.size()), "");
  uint32_t got[max_knn];
  for (uint32_t kr : {1u, std::max(1u, k / 2), k})
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        cell_neighbours(c, pts, x, y, kr, got);
        for (uint32_t j = 0; j < kr; ++j)
          ASSERT_EQ(got[j], t.at(x, y, j)) << "pixel " << x << "," << y << " rank " << j << " of " << kr
                                           << ", k=" << k << ", fraction " << fraction;
      }
}

TEST(KnnCells, GiveTheTablesNeighboursAtEveryPixelForEveryK) {
  for (auto [w, h, s, k] : {std::tuple{48, 40, 1.0, 20u}, {40, 32, 3.0, 32u}, {36, 30, 1.0, 1u}, {30, 40, 2.0, 5u}})
    for (double fraction : {0.5, 1.0, 4.0}) {
      const std::vector<point> pts = throw_darts(small_model(w, h, 1.0, s), quick_darts());
      expect_cells_equal_table(pts, 2 * w, 2 * h, k, fraction);
    }
}

TEST(KnnCells, GiveTheTablesNeighboursOnAGridFoveaAndALatticeOfTies) {
  // Grid points sit on pixel centres: exact ties between neighbours everywhere.
  const spacing_model m = partial_grid_model();
  expect_cells_equal_table(throw_darts(m, grid_darts()), 2 * m.display.width, 2 * m.display.height, 20, 1.0);
  const pointset uniform = uniform_pointset({40, 30, 1.0}, 1.0 / 8, knn_params{});
  expect_cells_equal_table(uniform.points, uniform.canvas_width(), uniform.canvas_height(), 12, 1.0);
  // Sets made with cells: the same points, cells and no table.
  knn_params kp;
  kp.k = 7;
  const pointset uniform_cells = uniform_pointset({40, 30, 1.0}, 1.0 / 8, kp, knn_storage::cells);
  EXPECT_EQ(uniform_cells.storage(), knn_storage::cells);
  EXPECT_EQ(uniform_cells.table.k, 0u);
  EXPECT_EQ(uniform_cells.cells.k, 7u);
  EXPECT_EQ(uniform_cells.points.size(), uniform.points.size());
  const pointset darts_cells = generate_pointset(small_model(30, 20), quick_darts(), kp, knn_storage::cells);
  EXPECT_EQ(darts_cells.storage(), knn_storage::cells);
  EXPECT_EQ(darts_cells.points.size(), throw_darts(small_model(30, 20), quick_darts()).size());
  EXPECT_EQ(knn_cells_problem(darts_cells.cells, darts_cells.points.size()), "");
}

TEST(KnnCells, CellsFollowTheSpacing) {
  // Far from the gaze the tiles' cells are wider and fewer; the candidates per cell stay
  // near k rather than growing with the cell.
  const spacing_model m = small_model(320, 240, 10.0, 4.0);
  const std::vector<point> pts = throw_darts(m, quick_darts());
  knn_cells_params cp;
  const knn_cells c = build_knn_cells(pts, 640, 480, cp);
  const uint32_t centre = (240 / knn_cells::tile) * c.tiles_x() + 320 / knn_cells::tile;
  const uint32_t corner = 0;
  EXPECT_LT(c.tiles[centre] & 7u, c.tiles[corner] & 7u);
  EXPECT_LT(c.cell_count(), uint64_t(640) * 480 / 4);  // far fewer cells than pixels
  const double per_cell = double(c.candidates.size()) / double(c.cell_count());
  EXPECT_GT(per_cell, cp.k);
  EXPECT_LT(per_cell, 4.0 * cp.k);
  // Memory follows the points: a few hundred bytes each, a fraction of the table's.
  EXPECT_LT(double(c.bytes()) / double(pts.size()), 400.0);
  EXPECT_LT(c.bytes(), knn_table_bytes(m.display, cp.k) / 4);
}

TEST(KnnCells, TraceTheTablesPointsForEveryGaze) {
  // A set keeping cells traces exactly the points the same set with its table does: the
  // band scan (its radii are bounds, not the table's exact radii) and the index alike.
  for (bool grid : {false, true}) {
    const testing::table_and_cells both =
        testing::both_ways(grid ? partial_grid_model() : small_model(160, 120, 10.0, 4.0), grid ? grid_darts() : quick_darts(), 12);
    const pointset &with_table = both.table, &with_cells = both.cells;
    for (uint32_t j = 0; j < 12; ++j)  // bounds at least the exact radii
      ASSERT_GE(with_cells.cells.radius_by_rank[j], with_table.table.radius_by_rank[j]) << "rank " << j;
    for (uint32_t k_used : {1u, 5u, 12u}) {
      const traced_index by_table = make_traced_index(with_table, k_used), by_cells = make_traced_index(with_cells, k_used);
      for (size_t i = 0; i < with_table.points.size(); ++i) {
        ASSERT_EQ(by_table.reaches[i].min_x, by_cells.reaches[i].min_x) << i;
        ASSERT_EQ(by_table.reaches[i].max_y, by_cells.reaches[i].max_y) << i;
      }
      EXPECT_EQ(by_table.margin, by_cells.margin);
      const double w = with_table.model.display.width, h = with_table.model.display.height;
      for (gaze_point g : {gaze_point{w / 2, h / 2}, gaze_point{0, 0}, gaze_point{w, h / 3}, gaze_point{w / 5, h}}) {
        const std::vector<uint32_t> expected = traced_points(with_table, g, k_used);
        EXPECT_FALSE(expected.empty());
        EXPECT_EQ(traced_points(with_cells, g, k_used), expected) << "k " << k_used;
        EXPECT_EQ(traced_points(with_cells, by_cells, g), expected) << "k " << k_used;
      }
    }
  }
}

TEST(KnnCells, SameCellsForAnyThreadCount) {
  const std::vector<point> pts = throw_darts(small_model(64, 48), quick_darts());
  knn_cells a, b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    a = build_knn_cells(pts, 128, 96, {});
  }
  b = build_knn_cells(pts, 128, 96, {});
  EXPECT_EQ(a.tiles, b.tiles);
  EXPECT_EQ(a.cell_start, b.cell_start);
  EXPECT_EQ(a.candidates, b.candidates);
}

TEST(KnnCells, RefuseBadParamsAndReportBrokenCells) {
  const std::vector<point> pts = throw_darts(small_model(32, 24), quick_darts());
  knn_cells_params p;
  p.k = 0;
  EXPECT_THROW(build_knn_cells(pts, 64, 48, p), std::invalid_argument);
  p.k = max_knn + 1;
  EXPECT_THROW(build_knn_cells(pts, 64, 48, p), std::invalid_argument);
  p.k = 5;
  p.cell_fraction = 0;
  EXPECT_THROW(build_knn_cells(pts, 64, 48, p), std::invalid_argument);
  p.cell_fraction = 1;
  EXPECT_THROW(build_knn_cells(std::vector<point>(pts.begin(), pts.begin() + 3), 64, 48, p), std::invalid_argument);
  const knn_cells good = build_knn_cells(pts, 64, 48, p);
  EXPECT_EQ(knn_cells_problem(good, pts.size()), "");
  knn_cells bad = good;
  bad.candidates[3] = uint32_t(pts.size());
  EXPECT_NE(knn_cells_problem(bad, pts.size()), "");
  bad = good;
  bad.tiles[1] ^= 1u;  // another level: the tiles' cells no longer add up
  EXPECT_NE(knn_cells_problem(bad, pts.size()), "");
  bad = good;
  bad.cell_start[1] = bad.cell_start[0] + 2;  // fewer than k candidates
  EXPECT_NE(knn_cells_problem(bad, pts.size()), "");
  bad = good;
  bad.tiles.pop_back();
  EXPECT_NE(knn_cells_problem(bad, pts.size()), "");
}

}  // namespace
}  // namespace fov
