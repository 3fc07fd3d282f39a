// Pictures fovgen writes: every point of a set (its line plots go through plot.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fov/pointset.h"

namespace fov {

// Every point as a dot on the canvas (thesis Fig. 12). With a gaze, the screen
// window is outlined, on-screen points are black, off-screen points the renderer
// must still trace are red and unused points grey.
void plot_points(const pointset& set, const std::string& path, std::optional<gaze_point> gaze, uint32_t k_used);


}  // namespace fov
