// The per-frame gaze log (fovview --gaze-log), and reading it back to replay a session
// frame for frame (fovview --gaze-replay). Columns in docs/fovview.md, "Gaze log".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "gaze_conditioning.h"

namespace fov {

// One frame's gaze: what the conditioner gave and when.
struct gaze_log_row {
  uint64_t frame = 0;
  double local_ms = 0;  // when the gaze was read, from the start
  gaze_estimate estimate;
  double sample_local_ms = 0;  // the newest sample's time, from the start (NaN: none yet)
  double shown_ms = 0;
};

std::string gaze_log_header();  // with its newline
std::string gaze_log_line(const gaze_log_row& r);  // with its newline

// The largest log read back (a row is about 150 bytes: an hour at 200 fps).
constexpr uintmax_t max_gaze_log_bytes = uintmax_t(256) << 20;

// Reads a log gaze_log_line wrote: the header, then frames 0, 1, 2, ... in order. Throws
// std::runtime_error "FILE:LINE: reason".
std::vector<gaze_log_row> read_gaze_log(const std::string& path);

}  // namespace fov
