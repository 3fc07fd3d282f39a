// The gaze-contingent viewer's loop: the window, the gaze source, the keys, the overlay,
// screenshots and frame statistics, over the shared renderer.
#pragma once

#include <cstdint>
#include <string>

#include "../common/gaze_flags.h"
#include "fov/renderer.h"

namespace fov {

// What fovview does beyond the render parameters (its flags; docs/fovview.md).
struct viewer_options {
  std::string scene = "builtin";
  std::string points, points_dir;  // one of the two
  double scale = 0;                // with points_dir: the scale to start at (0: the smallest)
  std::string display;             // with points_dir: the display whose sets to show (a spec; empty: the only one)
  gaze_options gaze;               // a tracker or a trace (none: the mouse or fixed_gaze)
  std::string fixed_gaze;
  std::string gaze_log;            // a CSV of the gaze each frame used
  std::string gaze_replay;         // a gaze log to replay frame for frame (instead of a gaze source)
  std::string camera_path;
  uint32_t frames = 0;             // stop after N frames (0: run until Q)
  long screenshot_frame = -1;      // save this frame (from 0) to screenshot_file
  std::string screenshot_file, screenshot_dir = ".", compare;
  bool no_taa = false, exit_after = false, json = false, pipeline = false;
  double target_fps = 0;           // adapt rays per point to it (0: off)
};

// Opens the window and runs until Q, the window closes or o.frames frames; prints the JSON
// statistics with o.json. Throws usage_error for settings a set contradicts (k, scale).
int run_viewer(const viewer_options& o, render_params settings);

}  // namespace fov
