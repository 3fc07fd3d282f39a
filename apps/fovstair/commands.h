// fovstair's commands: run a session (a window or a simulated observer), simulate a
// rule, analyse sessions, validate a protocol. Each takes its flags as a struct.
#pragma once

#include "../common/gaze_flags.h"
#include <cstdint>
#include <string>
#include <vector>

namespace fov {

struct run_options {
  std::string protocol, subject, session, out_dir = "data", observer;
  bool resume = false;
  uint64_t stop_after = 0;  // testing: exit abruptly after N trials, as a crash would
  gaze_options gaze;  // a tracker or a trace (none: the mouse with gaze_mouse, else the fixation target)
  bool gaze_mouse = false;
  std::string script_keys;  // testing: the window's answers, one key per trial
  double screen_ppd = 0;    // the screen's pixels per degree for the subject (0: frames 1:1)
  bool fullscreen = false;
};
int run_session(const run_options& o);

// Rule settings simulate may vary without editing the protocol (negative: keep).
struct rule_overrides {
  double step = -1, initial_step = -1, start = -1;
  int64_t thresholds = -1, discard = -1;
};
struct simulate_options {
  std::string protocol, observer;
  uint32_t runs = 1000;
  bool json = false;
  rule_overrides overrides;
  std::vector<std::string> procedures;  // labels or "all"; empty: the protocol's
};
int simulate(const simulate_options& o);

struct analyze_options {
  std::vector<std::string> inputs;  // session files
  std::string thresholds, out_csv, plots;  // plots: none unless given
  bool json = false;
  std::vector<std::string> fits{"weibull", "logistic", "normal"};  // psychometric families, or "none"
  uint32_t bootstrap = 200;
};
int analyze(const analyze_options& o);

struct export_command_options {
  std::vector<std::string> inputs;  // session files
  std::string format = "psychopy", out_dir, task = "foveation";
};
int export_command(const export_command_options& o);

int validate_protocol(const std::string& protocol);

}  // namespace fov
