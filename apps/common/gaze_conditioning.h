// From a gaze source's raw samples to the gaze a frame is rendered at: confidence threshold,
// optional 1-euro smoothing, saccade detection by angular velocity (I-VT) and the dropout
// policy. One conditioner per source, fed every frame (docs/fovview.md, "Gaze conditioning").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fov/display.h"
#include "fov/labels.h"
#include "gaze_source.h"

namespace fov {

struct gaze_conditioning {
  // Samples below this confidence are dropped (counted). Pupil Labs' own tools treat gaze
  // under 0.6 as unreliable; sources without a confidence give 1.
  double min_confidence = 0.6;
  // The 1-euro filter (Casiez, Roussel and Vogel, CHI 2012): a low-pass filter whose cutoff
  // rises with speed, fc = min_cutoff_hz + beta * |speed| (speed in degrees per second).
  // min_cutoff_hz 0: no smoothing. The derivative's own cutoff is 1 Hz, as in the paper.
  double min_cutoff_hz = 0;
  double beta = 0;
  // I-VT (Salvucci and Goldberg 2000): a sample moving faster than this (degrees of visual
  // angle per second, between consecutive samples) belongs to a saccade; the first slower one
  // after a saccade is its landing. 30 deg/s is Tobii's I-VT default (Olsen 2012). 0: off.
  double saccade_deg_s = 30;
  // Dropout (live sources only): with no valid sample, hold the last gaze this long, then
  // go to the safe mode (the screen's centre) until a valid sample arrives.
  double hold_ms = 200;
};

enum class gaze_state { tracking, saccade, holding, safe };
inline constexpr label_table<gaze_state, 4> gaze_state_labels = {
    {"tracking", gaze_state::tracking}, {"saccade", gaze_state::saccade}, {"holding", gaze_state::holding},
    {"safe", gaze_state::safe}};

// The gaze for one frame and how it came about.
struct gaze_estimate {
  gaze_point at;                 // what to render at
  gaze_state state = gaze_state::tracking;
  bool landed = false;           // a saccade ended with this update
  gaze_point saccade_onset;      // with `landed`: where the eye was when the saccade began
  gaze_sample newest;            // the newest valid sample (raw, before smoothing)
  bool has_sample = false;       // whether any valid sample was ever seen
  double age_ms = 0;             // now - newest.t_ms: how old the sample is at this update
  uint32_t fresh = 0;            // valid samples this update
};

class gaze_conditioner {
 public:
  gaze_conditioner(const gaze_conditioning& params, const display_geometry& display, bool live);
  // Feeds this frame's samples (oldest first) and returns the gaze at `now_ms`.
  gaze_estimate update(double now_ms, const std::vector<gaze_sample>& samples);

  uint64_t low_confidence = 0;  // samples dropped under min_confidence
  uint64_t saccades = 0;        // saccades that landed
  uint64_t dropouts = 0;        // times the safe mode was entered
  double safe_ms = 0;           // time spent in the safe mode

 private:
  double degrees_between(gaze_point a, gaze_point b) const;
  gaze_conditioning p_;
  display_geometry display_;
  bool live_;
  gaze_estimate last_;
  gaze_point filtered_{}, onset_{};
  double filtered_speed_ = 0, last_update_ms_ = 0;
  bool in_saccade_ = false, filter_started_ = false, updated_ = false;
};

// "" when the params are usable, else why not (naming the flag that sets the field).
std::string gaze_conditioning_problem(const gaze_conditioning& p);

}  // namespace fov
