// The flicker experiment: how much a foveated frame changes from one frame to the next
// along a slow camera turn with a drifting gaze, raw and with TAA, beside what the
// full-resolution reference itself changes.
#pragma once

#include <cstdint>

#include "fov/renderer.h"

namespace fov {

struct flicker_params {
  uint32_t frames = 8;               // 2 or more
  float yaw_deg_per_frame = 0.15f;   // the camera turns right about its up axis
  double gaze_px_per_frame = 3;      // the gaze drifts right (clamped to the screen)
};

// Mean frame-to-frame change of display luminance (mean_luminance_change), over frames - 1 pairs.
struct flicker_report {
  double raw = 0;        // the reconstructed frames
  double taa = 0;        // the same samples blended by TAA (p.temporal)
  double reference = 0;  // full-resolution frames at p.spp rays per pixel
};

// Each frame is traced once with the pattern fixed (p.seed: the rays move only with the
// camera) and reconstructed twice, without and with TAA, from the same samples; the
// reference is traced with the same seed. The renderer's camera and TAA history are
// restored afterwards.
flicker_report measure_flicker(renderer& r, gaze_point start, const render_params& p, const flicker_params& f = {});

}  // namespace fov
