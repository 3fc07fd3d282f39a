// Poisson-disc dart throwing with a spatially varying minimum distance.
#pragma once

#include <functional>
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

// Sorts points by Morton code (ties by position), in place.
void sort_morton(std::vector<point>& points);

}  // namespace fov
