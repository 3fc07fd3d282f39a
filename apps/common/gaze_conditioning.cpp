#include "gaze_conditioning.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace fov {

namespace {

// The 1-euro filter's smoothing factor for cutoff `fc` (Hz) over `dt_s` seconds.
double smoothing(double fc, double dt_s) {
  const double tau = 1 / (2 * M_PI * fc);
  return 1 / (1 + tau / dt_s);
}

}  // namespace

std::string gaze_conditioning_problem(const gaze_conditioning& p) {
  if (!(p.min_confidence >= 0 && p.min_confidence <= 1)) return "--gaze-min-confidence must lie in 0..1";
  if (!(p.min_cutoff_hz >= 0 && p.min_cutoff_hz <= 1000)) return "--gaze-filter: the minimum cutoff must lie in 0..1000 Hz";
  if (!(p.beta >= 0 && p.beta <= 1000)) return "--gaze-filter: beta must lie in 0..1000";
  if (p.beta > 0 && p.min_cutoff_hz == 0) return "--gaze-filter: beta needs a minimum cutoff above 0";
  if (!(p.saccade_deg_s >= 0 && p.saccade_deg_s <= 5000)) return "--saccade-deg-s must lie in 0..5000 (0: off)";
  if (!(p.hold_ms >= 0 && p.hold_ms <= 60000)) return "--gaze-hold-ms must lie in 0..60000";
  return "";
}

gaze_conditioner::gaze_conditioner(const gaze_conditioning& params, const display_geometry& display, bool live)
    : p_(params), display_(display), live_(live) {
  last_.at = screen_centre(display);
  last_.state = live ? gaze_state::safe : gaze_state::tracking;
}

// The visual angle between two screen points seen from the viewing position (on the axis
// through the screen's centre, v display widths away).
double gaze_conditioner::degrees_between(gaze_point a, gaze_point b) const {
  const double d = display_.width * display_.viewing_distance;
  const double ax = a.x - 0.5 * display_.width, ay = a.y - 0.5 * display_.height;
  const double bx = b.x - 0.5 * display_.width, by = b.y - 0.5 * display_.height;
  const double cx = ay * d - d * by, cy = d * bx - ax * d, cz = ax * by - ay * bx;  // a x b
  const double dot = ax * bx + ay * by + d * d;
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot) * 180 / M_PI;
}

gaze_estimate gaze_conditioner::update(double now_ms, const std::vector<gaze_sample>& samples) {
  gaze_estimate e = last_;
  e.landed = false;
  e.fresh = 0;
  bool restart = e.state == gaze_state::safe;
  for (const gaze_sample& s : samples) {
    if (s.confidence < p_.min_confidence) {
      ++low_confidence;
      continue;
    }
    const gaze_point at{s.x, s.y};
    // The first sample, or the first after a dropout: no velocity to the last one.
    if (!e.has_sample || restart) {
      restart = false, in_saccade_ = false;
      filtered_ = at, filter_started_ = false;
    } else {
      const double dt_s = (s.t_ms - e.newest.t_ms) / 1000;
      if (dt_s >= 0.0005) {  // samples stamped alike (one read) carry no velocity
        const double speed = degrees_between({e.newest.x, e.newest.y}, at) / dt_s;
        const bool fast = p_.saccade_deg_s > 0 && speed > p_.saccade_deg_s;
        if (fast && !in_saccade_) in_saccade_ = true, onset_ = {e.newest.x, e.newest.y};
        if (!fast && in_saccade_) {
          in_saccade_ = false, e.landed = true, e.saccade_onset = onset_, ++saccades;
          filtered_ = at, filter_started_ = false;  // the filter starts afresh where the eye landed
        }
        if (p_.min_cutoff_hz > 0 && !in_saccade_ && !e.landed) {
          // 1-euro: the speed (deg/s) low-passed at 1 Hz sets the position's cutoff.
          const double raw_speed = degrees_between(filtered_, at) / dt_s;
          filtered_speed_ = filter_started_ ? filtered_speed_ + smoothing(1.0, dt_s) * (raw_speed - filtered_speed_) : raw_speed;
          filter_started_ = true;
          const double a = smoothing(p_.min_cutoff_hz + p_.beta * filtered_speed_, dt_s);
          filtered_.x += a * (at.x - filtered_.x);
          filtered_.y += a * (at.y - filtered_.y);
        } else {
          filtered_ = at;
        }
      } else {
        filtered_ = p_.min_cutoff_hz > 0 && filter_started_ ? filtered_ : at;
      }
    }
    e.newest = s, e.has_sample = true;
    ++e.fresh;
  }
  const double elapsed = updated_ ? std::max(0.0, now_ms - last_update_ms_) : 0;
  updated_ = true, last_update_ms_ = now_ms;
  if (e.has_sample) e.age_ms = now_ms - e.newest.t_ms;
  if (!live_ && e.fresh == 0 && in_saccade_) {
    // A replay, the mouse or a fixed gaze gives nothing new: the eye stays at its last
    // sample, so a saccade in progress has landed there.
    in_saccade_ = false, e.landed = true, e.saccade_onset = onset_, ++saccades;
    filtered_ = {e.newest.x, e.newest.y}, filter_started_ = false;
  }
  if (e.fresh > 0 || (!live_ && e.has_sample)) {
    e.state = in_saccade_ ? gaze_state::saccade : gaze_state::tracking;
    e.at = p_.min_cutoff_hz > 0 ? filtered_ : gaze_point{e.newest.x, e.newest.y};
  } else if (live_ && e.has_sample && e.age_ms <= p_.hold_ms) {
    e.state = gaze_state::holding;  // e.at stays
  } else if (live_) {
    if (e.state != gaze_state::safe && e.has_sample) ++dropouts;
    if (e.state == gaze_state::safe && e.has_sample) safe_ms += elapsed;
    e.state = gaze_state::safe;
    e.at = screen_centre(display_);
    in_saccade_ = false;
  }
  last_ = e;
  return e;
}

}  // namespace fov
