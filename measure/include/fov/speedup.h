// Timing that holds up on a shared machine: repeated measurements summarised with their
// spread, and speedups as ratios of neighbouring runs (a foveated frame and a
// full-resolution frame with the same rays per sample, timed one right after the other).
#pragma once

#include <cstdint>
#include <vector>

#include "fov/renderer.h"

namespace fov {

// Median and spread of repeated measurements.
struct timing {
  double median = 0, min = 0, max = 0;
};
// v not empty; the median of an even count is the mean of the middle two.
timing summarise(std::vector<double> v);

// Per repetition, a configuration's frame time and the full-resolution frame's timed
// beside it; speedup = full / frame per repetition, then summarised.
struct paired_timing {
  timing frame_ms, full_ms, speedup;
};
// Throws std::invalid_argument unless both hold the same, non-zero number of runs.
paired_timing pair_timings(const std::vector<double>& frame_ms, const std::vector<double>& full_ms);

// `repeats` times: a full-resolution frame (width x height, p.spp rays per pixel), then a
// foveated frame at the gaze with the renderer's set (its total: trace, reconstruction,
// TAA). The renderer should be warmed up; its TAA history moves on with each frame.
paired_timing measure_speedup(renderer& r, gaze_point gaze, const render_params& p, int width, int height, uint32_t repeats);

}  // namespace fov
