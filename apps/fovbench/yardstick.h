// `fovbench --yardstick`: the thesis's observers as a yardstick for the metric. The study's
// conditions (thesis Sec. 6, Table 5: 32 rays per point, TAA, k = 5, free viewing) judged by
// FovVideoVDP against the non-foveated frame with the same rays per pixel, over the sweep's
// scales and methods, with the view still and along the temporal path; where JOD falls 1
// below 10 set beside the scales at which observers saw foveation (NN 1.751, Shepard 1.779,
// RBF 1.675).
#pragma once

#include <string>
#include <vector>

#include "bench.h"
#include "fov/fvvdp.h"

namespace fov {

// One condition: a scene, gaze, path (still or moving), scale, method and k, over
// --temporal-frames frames at --temporal-fps.
struct yardstick_row {
  std::string scene, gaze, path;
  double scale = 0;
  std::string method;
  uint32_t k = 0, spp = 0;
  fvvdp_result taa, raw;  // video JOD of the TAA and raw sequences against the full-resolution frames
  double flicker_raw = 0, flicker_taa = 0;
};

// The scales observers' thresholds were measured at (thesis Table 5), by method label.
double thesis_threshold(const std::string& method);

// Where a JOD curve over scales first falls to `level`: linear between the scales around
// the crossing; NaN when it never does (or starts below it).
double scale_at_jod(const std::vector<double>& scales, const std::vector<double>& jod, double level);

// Runs every condition (the sweep's scenes, gazes, scales, methods and spp; k from --k's
// first value, nn at 1) and writes -o/yardstick.csv, yardstick.md and the figure
// yardstick_jod (PNG, SVG). Returns the rows; lines for the user go to `report`.
std::vector<yardstick_row> run_yardstick(const bench_options& o, const bench_reporter& report);

}  // namespace fov
