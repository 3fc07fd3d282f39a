// The gaze flags fovview and fovstair share: which source, its calibration and the gaze's
// conditioning (docs/fovview.md, "Gaze sources" and "Gaze conditioning").
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "gaze_conditioning.h"
#include "gaze_source.h"

namespace fov {

struct gaze_options {
  std::string trace;        // --gaze-trace FILE
  std::string trace_columns;  // --gaze-trace-columns SPEC (another tool's export)
  int udp = 0;              // --gaze-udp PORT (0: none)
  std::string pupil;        // --gaze-pupil tcp://HOST:PORT
  std::string pupil_topic = "gaze.";
  std::string calibration;  // --gaze-calibration FILE (udp and pupil)
  std::vector<double> filter;  // --gaze-filter MIN_CUTOFF_HZ,BETA
  gaze_conditioning conditioning;
  int sources() const { return !trace.empty() + (udp != 0) + !pupil.empty(); }
};

void add_gaze_flags(CLI::App& app, gaze_options& o);

// Checks the flags (usage_error naming the flag) and fills o.conditioning from them.
void require_valid(gaze_options& o);

// The source the flags choose, for a width x height screen; null when they choose none
// (the tool's own default: the mouse, a fixed gaze or the fixation target). Throws
// std::runtime_error naming the file or address that fails.
std::unique_ptr<gaze_source> open_gaze(const gaze_options& o, int width, int height);

}  // namespace fov
