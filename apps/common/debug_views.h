// Overlays that show a researcher what the renderer did, drawn over a frame.
#pragma once

#include <string>

#include "fov/pointset.h"
#include "fov/trace.h"

namespace fov {

// view = "points": the frame darkened, each point on screen marked white at its position
//        for this gaze;
//        "density": the set's points per pixel, counted over 8 x 8-pixel blocks, as a heat
//        map (blue 0.001 .. green .. red 3 points per pixel, log scale);
//        "eccentricity": the frame with rings at 5, 10, 20, 30 and 45 degrees from the gaze.
// `set` may be null for a reference frame (eccentricity only).
frame debug_overlay(const std::string& view, const frame& image, const pointset* set, const double gaze[2]);

}  // namespace fov
