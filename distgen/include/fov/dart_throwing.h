// Poisson-disc dart throwing with a spatially varying minimum distance.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fov/pointset.h"

namespace fov {

// Throws darts over the 2W x 2H canvas (phase 1) and then over the central
// region (phase 2), each until saturation, and returns the accepted points in
// Morton order. A dart at distance d from the canvas centre is rejected when an
// accepted point lies closer than point_spacing_px(model, d).
//
// Runs in parallel on tiles at least as wide as the largest spacing, in four
// passes of non-adjacent tiles, each tile with its own random stream: the result
// depends on the parameters and seed only, never on the thread count.
std::vector<point> throw_darts(const spacing_model& model, const dart_params& params,
                               dart_stats* stats = nullptr);

// A nested set's points (fovgen --levels): level[i] is the first level whose set holds
// points[i], 0 the coarsest.
struct nested_points {
  std::vector<point> points;  // Morton order
  std::vector<uint8_t> level;
};

// "" when these scales (as --levels lists them: increasing, finest first) can make a nested
// set: 2..max_levels of them, positive, finite, strictly increasing. Else why, naming --levels.
std::string levels_problem(const std::vector<double>& scales);

// Throws a nested set: the coarsest level (the largest scale) exactly as throw_darts throws
// a set at that scale with these params (point for point), then each finer level's darts
// among the points already accepted, each keeping its own level's spacing from all of them,
// until saturation. So the points of levels 0..l form a Poisson-disc set at that level's
// scale (its spacing rule holds for every pair, and it is saturated as throw_darts's sets
// are), and a coarser level's points are a subset of every finer level's. model.scale is
// not read; params.fovea must be darts. stats sums both phases over the levels and probes
// the free area at the finest level.
nested_points throw_nested_darts(const spacing_model& model, const std::vector<double>& scales, const dart_params& params,
                                 dart_stats* stats = nullptr);

// Sorts points by Morton code (ties by position), in place.
void sort_morton(std::vector<point>& points);

}  // namespace fov
