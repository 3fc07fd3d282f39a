// Overlays that show a researcher what the renderer did, drawn over a frame.
#pragma once

#include <cstdint>
#include <string>

#include "fov/labels.h"

#include "fov/pointset.h"
#include "fov/frame.h"

namespace fov {

enum class debug_view : uint8_t { points, density, eccentricity, refinement };
inline constexpr std::pair<const char*, debug_view> debug_view_labels[] = {
    {"points", debug_view::points}, {"density", debug_view::density}, {"eccentricity", debug_view::eccentricity},
    {"refinement", debug_view::refinement}};

// view = points: the frame darkened, each point on screen marked white at its position
//        for this gaze;
//        density: the set's points per pixel, counted over 8 x 8-pixel blocks, as a heat
//        map (blue 0.001 .. green .. red 3 points per pixel, log scale);
//        eccentricity: the frame with rings at 5, 10, 20, 30 and 45 degrees from the gaze;
//        refinement: an adaptive frame's refinement map (`map`, of a set of `levels` levels):
//        each block tinted by the level it reads (blue the coarsest .. red the finest)
//        over the frame at half brightness.
// `set` may be null for a reference frame (eccentricity only).
frame debug_overlay(debug_view view, const frame& image, const pointset* set, gaze_point gaze,
                    const refinement_map* map = nullptr, uint32_t levels = 1);

}  // namespace fov
