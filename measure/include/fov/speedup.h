// Timing that holds up on a shared machine: repeated measurements summarised with their
// spread, and speedups as ratios of neighbouring runs (a foveated frame and a
// full-resolution frame with the same rays per sample, timed one right after the other).
#pragma once

#include <cstdint>
#include <cmath>
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
  std::vector<double> ratios;  // full / frame per repetition, in order (for chained_speedup)
};
// Throws std::invalid_argument unless both hold the same, non-zero number of runs.
paired_timing pair_timings(const std::vector<double>& frame_ms, const std::vector<double>& full_ms);

// A speedup with its bootstrap confidence interval.
struct speedup_interval {
  double estimate = 0, lo = 0, hi = 0;  // NaN when a sample is empty
  bool contains_one() const { return lo <= 1 && hi >= 1; }
};

// The speedup of a chain of paired measurements: `paired` holds per-repetition ratios
// full-resolution time / configuration time, each pair timed back to back (same spp), and
// `ladder` per-repetition ratios of the full-resolution frame it is compared with to the
// one it was paired with, also timed back to back (empty: the same frame, ratio 1). The
// estimate is median(paired) x median(ladder); the interval, the `level` percentile
// interval of that product over `resamples` bootstrap resamples of both samples
// (independently, with replacement, seeded: the same samples give the same interval).
speedup_interval chained_speedup(const std::vector<double>& paired, const std::vector<double>& ladder = {},
                                 double level = 0.95, uint32_t resamples = 4000, uint64_t seed = 1);

// CPU time of this process so far (every thread), in milliseconds.
double process_cpu_ms();

// `repeats` times: a full-resolution frame (width x height, p.spp rays per pixel), then a
// foveated frame at the gaze with the renderer's set (its total: trace, reconstruction,
// TAA). The renderer should be warmed up; its TAA history moves on with each frame.
paired_timing measure_speedup(renderer& r, gaze_point gaze, const render_params& p, int width, int height, uint32_t repeats);

}  // namespace fov
