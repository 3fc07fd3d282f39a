// The k nearest points of any canvas pixel, from storage that grows with the points rather
// than with the canvas's pixels: candidate lists on an adaptive grid of cells, refined per
// pixel when it is read.
//
// The canvas is cut into tiles of `tile` x `tile` pixels; each tile into square cells of
// 2^level pixels, its level chosen so that a cell is about as wide as the smallest point
// spacing in the tile (a pixel in the fovea, up to a whole tile far out). A cell keeps every
// point within d_k(c) + 2 delta of its centre c, where d_k(c) is the distance from c to its
// k-th nearest point and delta the farthest a pixel centre of the cell lies from c. For any
// pixel centre q of the cell and any k' <= k, q's k' nearest points lie within
// d_k'(q) + |q - c| <= d_k'(c) + 2 delta of c: the candidates, kept sorted by distance
// from c, hold them all in their prefix out to that radius. A reader ranks that prefix by
// distance to q in double, ties to the smaller index: the same neighbours, in the same
// order, as the exact table (knn_table.h) of the same points and k.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fov/pointset.h"

namespace fov {

struct knn_cells_params {
  uint32_t k = 20;  // the most neighbours a reader may ask for, 1..max_knn
  // A tile's cells are the largest power of two at most `cell_fraction` x the smallest
  // spacing of the points in the tile (1 .. tile pixels): smaller cells keep fewer
  // candidates each but more cells. Must lie in (0, 64].
  double cell_fraction = 1.0;
  // Past this many candidates in all the build stops and throws (0: no limit). Sets fovgen
  // makes keep a few k per point; points far from most of the canvas (a hostile file) make
  // far more, since a cell keeps every point out to its k-th neighbour's distance.
  uint64_t max_candidates = 0;
};

// Builds the cells of these points (parallel). Throws std::invalid_argument for k outside
// 1..max_knn, fewer points than k, a cell_fraction out of range, cells that would not fit
// in memory, or more candidates than params.max_candidates.
knn_cells build_knn_cells(const std::vector<point>& points, uint32_t canvas_width, uint32_t canvas_height,
                          const knn_cells_params& params);

// How many cells build_knn_cells would make of these points (cheap: one pass over them).
uint64_t count_knn_cells(const std::vector<point>& points, uint32_t canvas_width, uint32_t canvas_height,
                         double cell_fraction = knn_cells_params{}.cell_fraction);

// Sets cells.radius_by_tile, radius_by_rank and max_radius (bounds: see knn_cells); the
// builder calls it.
void set_cells_radii(knn_cells& cells, const std::vector<point>& points);

// Writes the k nearest points of canvas pixel (x, y)'s centre to out[0..k), nearest first
// (ties: smaller index); k must lie in 1..cells.k. Returns how many candidates it ranked.
uint32_t cell_neighbours(const knn_cells& cells, const std::vector<point>& points, uint32_t x, uint32_t y,
                         uint32_t k, uint32_t* out);

// Appends to `out` every point that cell_neighbours may return among the first k of a canvas
// pixel in [x0, x1) x [y0, y1) (clipped to the canvas): each meeting cell's prefix that those
// pixels rank. A superset of the points the rectangle's pixels read (exact per cell, the
// cells being what they are); indices may repeat. For the points a region needs traced.
void rect_neighbour_points(const knn_cells& cells, const std::vector<point>& points, uint32_t x0, uint32_t y0,
                           uint32_t x1, uint32_t y1, uint32_t k, std::vector<uint32_t>& out);

// "" when cells agree with their points: sizes match the canvas, every tile's cells lie in
// the cell array, offsets ascend, every candidate names a point, and each cell holds at
// least k candidates. Otherwise what is wrong (for cells made or changed by hand: tests, the
// fuzz target; files never hold cells, loaders build them).
std::string knn_cells_problem(const knn_cells& cells, size_t point_count);

}  // namespace fov
