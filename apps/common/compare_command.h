// `fovbench compare`: two image files scored as every tool scores a frame (fov/comparison.h).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "fov/comparison.h"

namespace fov {

// `fovbench compare`: two image files, the display they are seen on and the gaze.
struct compare_options {
  std::string test, reference;
  std::string display;             // a display spec (require_display; empty: the images' size)
  double viewing_distance = 0;     // display widths (0: the display's, 1 for WxH)
  std::string gaze = "centre";
  bool json = false, flip = true, jod = true;
  display_photometry photometry;
  std::string flip_map, foveated_flip_map;
  // Video: `frames` frames at `fps`; TEST (and REFERENCE, else a still image shown every
  // frame) name them with one %d or %0Nd, numbered from 0. JOD only (FovVideoVDP's video mode).
  double fps = 0;
  int frames = 0;
};

// PATTERN with its one %d or %0Nd (N a digit) replaced by n; throws usage_error naming
// `flag` when the pattern holds another conversion or none (`required`).
std::string frame_path(const std::string& flag, const std::string& pattern, int n, bool required);

// --peak-luminance, --contrast, --ambient: the display's light for JOD (fov/fvvdp.h), bound
// to `p`, each refused (exit 2, naming the flag and its range) outside photometry_problem's ranges.
void add_photometry_flags(CLI::App& app, display_photometry& p);
// Reads both, checks sizes (usage_error for flags, file_error for files), compares and
// writes the maps; returns what to print (JSON or the two lines).
std::string run_compare(const compare_options& o);

// An error map as a grey image: byte = round(255 x error). Written as write_frame does.
void write_error_map(const error_map& map, const std::string& path);

}  // namespace fov
