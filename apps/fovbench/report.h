// fovbench's options, figures (pareto.png, error_by_eccentricity.png, speedup_vs_scale.png)
// and report.md, made from the rows of results.csv.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fov/renderer.h"
#include "sweep.h"

namespace fov {

struct bench_options {
  std::vector<std::string> scenes;
  std::string display = "fove";
  std::vector<double> scales{1.0};
  std::vector<method> methods;
  std::vector<uint32_t> ks{5};
  std::vector<uint32_t> spps{4};
  std::vector<std::string> gazes{"centre"};
  std::string out = "out/bench";
  std::string points_dir = "precomputed";
  // Settings every configuration shares (seed, shadows, texture footprint, RBF kernel and
  // shape, Renka, device, camera); method, k and spp come from the lists above.
  render_params render;
  uint32_t frames = 3;
  uint32_t temporal_frames = 0;
  bool resume = false;
  double budget_psnr = std::numeric_limits<double>::quiet_NaN();
  double budget_foveated = std::numeric_limits<double>::quiet_NaN();
};

void write_bench_figures(const std::vector<result_row>& rows, const bench_options& o, const std::string& dir);
void write_bench_report(const std::vector<result_row>& rows, const bench_options& o, const std::string& path, int argc,
                        char** argv);

}  // namespace fov
