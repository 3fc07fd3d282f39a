// Temporal anti-aliasing: blends each new frame with the reprojected previous output
// (thesis Secs. 2.5 and 3.1; colour clipping as in Patney et al. and the TWFR paper).
#pragma once

#include "fov/acuity.h"
#include "fov/camera.h"
#include "fov/frame.h"

namespace fov {

struct taa_params {
  float alpha = 0.1f;        // weight of the current frame
  float clip_gamma = 1.0f;   // history clipped into mean +- gamma sigma of the current 3x3 neighbourhood
  float focus_lag_deg = 5;   // where a pixel's eccentricity dropped by this much, take the current frame
};

// The previous output and how it was seen. Starts empty: the first frame passes through.
struct taa_state {
  frame history;
  camera cam;
  gaze_point gaze;
  bool valid = false;
  uint64_t generation = 0;  // advanced by every resolve (device copies of the history check it)
};

// Blends `current` (rendered with `cam`, gaze at `gaze` on `display`) with the history:
//  1. reprojection: each pixel's world position (from its depth; +inf depth is taken as
//     a direction) is projected into the previous camera and the history read there
//     bilinearly; pixels that fall outside it take the current frame;
//  2. clipping: the history is moved along the line towards the current colour c until
//     it lies in the box mean +- clip_gamma sigma of the current 3x3 neighbourhood,
//     widened to contain c (so the result always lies between c and the history);
//  3. blending: out = a current + (1 - a) history, a = alpha, raised towards 1 in
//     proportion to how far the pixel's eccentricity dropped (up to focus_lag_deg).
// Returns the output and makes it the new history.
frame taa_resolve(taa_state& state, const frame& current, const camera& cam, const display_geometry& display,
                  gaze_point gaze, const taa_params& params = {});

// Makes `output` (seen with `cam`, gaze at `gaze`) the history of the next resolve.
// taa_resolve calls it; so does any other path that resolves frames (cl_reconstruct.h).
void taa_remember(taa_state& state, const frame& output, const camera& cam, gaze_point gaze);

}  // namespace fov
