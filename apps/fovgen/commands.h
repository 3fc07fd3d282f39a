// fovgen's commands: generate a set, describe it (info), draw it (plot), generate a family
// over scales (sweep). main() binds the flags into these structs and calls one of them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "fov/dart_throwing.h"
#include "fov/knn_table.h"

namespace fov {

struct generate_options {
  std::string display;  // preset name, or empty
  int width = 1280, height = 1440;
  double viewing_distance = 1.0;
  double scale = 1.0;
  uint32_t k = 20;
  uint32_t group = 4;
  uint64_t seed = 1;
  uint32_t saturation = dart_params{}.saturation_rejections;
  std::string encoding = "ref-left-zstd";
  fovea_layout fovea = dart_params{}.fovea;
  double grid_spacing = dart_params{}.grid_spacing;
  // The acuity model and its parameters (docs/schemes.md); pivots: piecewise-mar's five acuities.
  acuity_params acuity;
  std::vector<double> pivots;
  point_sampler sampler = point_sampler::poisson;
  bool json = false;
  std::string output;  // the set's file (generate only)
  // Nested set (generate only): the levels' scales, finest first (e.g. 0.7,1.0,1.5,2.25,3.0);
  // empty for a set of one scale.
  std::vector<double> levels;
  bool scale_given = false;
  // Which flags were given (with --display, only given ones replace the preset's).
  bool width_given = false, height_given = false, distance_given = false, grid_spacing_given = false;
  bool mar_given = false;  // --mar-slope, --mar-fovea or --mar-dead-zone
};
// Binds the flags every generating command takes (not --scale and -o, which differ).
void add_generate_flags(CLI::App& app, generate_options& o);
// Fills the *_given fields from a parsed command line.
void note_given_flags(const CLI::App& app, generate_options& o);

struct info_options {
  std::string file, gaze;
  uint32_t k = 0;  // neighbours the renderer reads (0: all stored)
  bool json = false;
};
struct plot_options {
  std::string file, output, gaze;
  uint32_t k = 0;
};
struct sweep_options {
  generate_options generate;
  std::string scales = "1.0:3.0:0.1", dir;
  bool skip_existing = false;
};

// Each returns the exit code; usage_error for flags, file_error and runtime_error otherwise.
int run_generate(const generate_options& o);
int run_info(const info_options& o);
int run_plot(const plot_options& o);
int run_sweep(const sweep_options& o);
// The spacing every acuity model gives against eccentricity on one display (docs/schemes.md):
// a CSV table on stdout (or JSON), and with a stem a figure STEM.png and STEM.svg.
struct acuity_options {
  std::string display = "fove", output;
  double scale = 1.0;
  bool json = false;
};
int run_acuity(const acuity_options& o);
// The presets (or one display spec): size, viewing distance, pixels per degree, fields of view
// and the name its sets carry; a Markdown table, or JSON.
int run_displays(const std::string& spec, bool json);

}  // namespace fov
