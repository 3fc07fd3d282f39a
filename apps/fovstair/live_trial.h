// One trial shown to a person: the stimulus in the window, the answer from the keyboard.
#pragma once

#include <array>
#include <memory>
#include <vector>
#include <string>

#include "../common/gaze_conditioning.h"
#include "../common/gaze_source.h"
#include "../common/window.h"
#include "fov/renderer.h"
#include "protocol.h"
#include "session.h"

namespace fov {

struct trial_answer {
  bool quit = false;       // the person quit from the pause screen: nothing to record
  bool detected = false;   // yes-no: "yes"; 2AFC: picked the foveated interval
  std::string response;    // "yes"/"no" or "1"/"2"
  double rt_ms = 0;        // from the stimulus (or the question, 2AFC) to the key
  uint64_t gaze_samples = 0, gaze_clamped = 0;
  double gaze_mean[2] = {0, 0}, gaze_sd[2] = {0, 0};  // pixels
  double mean_frame_ms = 0;
  // The gaze on every frame of the stimulus: [ms since the stimulus began, x, y (pixels),
  // the newest sample's age when read (ms), its tracker time (s)] (the last two NaN, null in
  // JSON, without one), the first max_trial_gaze_samples; and its largest distance from
  // the fixation target.
  std::vector<std::array<double, 5>> gaze_trace;
  double fixation_max_deg = 0;
  bool fixation_broken = false;  // beyond the protocol's fixation_control radius
};

// The most gaze samples a trial record keeps (minutes of frames at 100 Hz).
constexpr size_t max_trial_gaze_samples = 20000;

struct live_context {
  const stair_protocol& protocol;
  fov::renderer& renderer;
  view_window& window;
  gaze_source* gaze = nullptr;  // null: the gaze is the fixation target
  gaze_conditioner* conditioner = nullptr;  // with gaze: its conditioning
  // Testing: answers taken from here, one character per answer, instead of the keyboard
  // (each stimulus still shows at least one frame; breaks do not wait). Empty: keyboard.
  std::string scripted_keys;
};

// Shows a break screen when planned, a fixation cross, then the stimulus (live frames at
// the current gaze) until Y/N (yes-no) or after two intervals until 1/2 (2AFC). Esc pauses;
// in the pause Q quits, any other key resumes the trial from its start.
trial_answer run_live_trial(live_context& ctx, const trial_plan& t, const pointset& set);

// The protocol's instructions (instruction_lines) until Space; false when Q quits (or the
// window closes). With scripted keys it does not wait.
bool show_instructions(live_context& ctx, int width, int height);
// A line of feedback after a practice trial, for 800 ms.
void show_feedback(live_context& ctx, int width, int height, const std::string& text);

}  // namespace fov
