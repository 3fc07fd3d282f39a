// Where the viewer is looking, from one of several sources behind one interface.
//
// Conventions (docs/fovview.md, "Gaze sources"): positions are screen pixels, (0, 0) the
// top-left corner of the top-left pixel, y down (fov::gaze_point). Sources that send
// normalised positions use the same orientation, 0..1 across the width and height; a
// tracker whose origin is elsewhere (Pupil Labs' norm_pos: bottom-left) is turned into it by
// its source. Times are milliseconds on one local clock, gaze_clock_ms().
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "fov/acuity.h"
#include "fov/labels.h"

namespace fov {

// The local clock every gaze time is on: a steady clock, milliseconds.
double gaze_clock_ms();

enum class gaze_eye { both, left, right };
inline constexpr label_table<gaze_eye, 3> gaze_eye_labels = {
    {"both", gaze_eye::both}, {"left", gaze_eye::left}, {"right", gaze_eye::right}};

// One gaze measurement.
struct gaze_sample {
  double x = 0, y = 0;  // screen pixels, clamped to the screen
  double t_ms = 0;      // when the eye was there, on gaze_clock_ms(): the tracker's time mapped
                        // to ours (tracker_clock) or, without one, the arrival time
  double tracker_s = std::numeric_limits<double>::quiet_NaN();  // the tracker's own stamp (s)
  double confidence = 1;                                         // 0..1 (1 when the source has none)
  gaze_eye eye = gaze_eye::both;
};

class gaze_source {
 public:
  virtual ~gaze_source() = default;
  // Appends the samples that arrived since the last call, oldest first; `now_ms` is
  // gaze_clock_ms() (a replay starts its time at the first call).
  virtual void read(double now_ms, std::vector<gaze_sample>& out) = 0;
  virtual std::string name() const = 0;
  // A live tracker can fall silent (gaze_conditioner's dropout policy applies to it); a
  // replay, a fixed gaze and the mouse cannot, and their last sample stands.
  virtual bool live() const { return false; }
  // Convenience: read() and return the newest position (the previous one when none came).
  gaze_point poll(double now_ms);

  uint64_t samples = 0;    // samples delivered
  uint64_t clamped = 0;    // samples outside the screen, clamped to it
  uint64_t malformed = 0;  // inputs that could not be read (skipped)
  uint64_t clock_jumps = 0;  // tracker times that left the mapping (tracker_clock), re-anchored
  std::string last_problem;  // why the latest malformed input was refused

 protected:
  void clamp_to_screen(double& x, double& y);
  void refuse(std::string why) { ++malformed, last_problem = std::move(why); }
  // Appends a sample at (x, y), taken at t_ms, clamped to the screen and counted.
  void emit(double x, double y, double t_ms, std::vector<gaze_sample>& out);
  int width_ = 0, height_ = 0;
  gaze_point last_{};
  bool have_last_ = false;
};

// Maps a tracker's timestamps (seconds on its own clock) to gaze_clock_ms(). The offset comes
// from a time request (sync: the tracker's answer bracketed by our send and receive times) or,
// without one, from the samples themselves as the smallest delay seen (a sample cannot arrive
// before it was taken). A sample whose mapped time lies in the future by more than the
// allowance, or more than `max_age_ms` in the past, means one clock jumped: the mapping is
// re-anchored on that sample's arrival and the jump counted.
class tracker_clock {
 public:
  explicit tracker_clock(double max_age_ms = 1000) : max_age_ms_(max_age_ms) {}
  void sync(double tracker_s, double send_ms, double receive_ms);
  // The local time of a sample stamped `tracker_s` that arrived at `arrival_ms` (never later
  // than the arrival).
  double to_local(double tracker_s, double arrival_ms);
  bool synced() const { return have_offset_; }
  double offset_ms() const { return offset_ms_; }  // local = tracker_s * 1000 + offset
  uint64_t jumps = 0;
  bool wants_sync = false;  // a jump was seen: ask the tracker for its time again

 private:
  double max_age_ms_, offset_ms_ = 0, allowance_ms_ = 2;
  bool have_offset_ = false, from_sync_ = false;
};

// A map from a tracker's normalised gaze (top-left convention, 0..1) to normalised screen
// positions: a 3x3 homography, row-major, identity by default (docs/fovview.md, "Calibration").
struct gaze_calibration {
  double h[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::string from;         // the file it came from ("" for the identity)
  double fit_rms = 0;       // a grid's fit: RMS residual, normalised screen units
  size_t fit_points = 0;    // a grid's points
  // (x, y) normalised -> normalised; false when the point maps to infinity.
  bool apply(double& x, double& y) const;
};
// Reads a calibration file, JSON, one of
//   {"offset": [OX, OY], "scale": [SX, SY]}       x' = SX x + OX, y' = SY y + OY
//   {"homography": [H11, H12, ..., H33]}           9 numbers, row-major
//   {"grid": [[TX, TY, SX, SY], ...]}              where the tracker put the gaze (TX, TY) while
//                                                  the eye was on a target at (SX, SY); 4 or more
//                                                  targets, fitted by least squares (OpenCV)
// Throws std::runtime_error "FILE: reason".
gaze_calibration read_gaze_calibration(const std::string& path);

// A fixed point (tests, fixation-only experiments).
std::unique_ptr<gaze_source> fixed_gaze(int width, int height, double x, double y);

// A recorded trace, replayed in real time from the first read: CSV with the header "t_ms,x,y"
// (pixels) or "t_ms,x_norm,y_norm" (0..1), rows in non-decreasing time. Throws
// std::runtime_error "FILE:LINE: reason" for a bad header, bad numbers or time going
// backwards. After the last row the gaze stays there.
std::unique_ptr<gaze_source> trace_gaze(const std::string& path, int width, int height);

// Which columns of another tool's export hold the gaze (--gaze-trace-columns): names from
// its header line (comma- or tab-separated, quotes stripped), the time's unit, and the
// coordinates: pixels, normalised with the origin top-left, or normalised with the origin
// bottom-left (Pupil's norm_pos).
enum class trace_coords : uint8_t { pixels, normalised, normalised_bottom_left };
struct trace_columns {
  std::string time, x, y, confidence;  // confidence: "" for none
  double ms_per_unit = 1;
  trace_coords coords = trace_coords::pixels;
};
// "pupil" (Pupil Player's gaze_positions.csv: gaze_timestamp in s, norm_pos_x/y from the
// bottom-left, confidence), or "TIME,X,Y[,CONFIDENCE][;time=ms|s|us][;coords=pixels|norm|norm-bottom-left]".
// Returns "" or why the spec is malformed.
std::string parse_trace_columns(const std::string& spec, trace_columns& out);
// The largest export read (Pupil's rows are long: two hours at 200 Hz is about 400 MB).
constexpr uintmax_t max_gaze_table_bytes = uintmax_t(512) << 20;
// A trace from an export's columns, replayed as trace_gaze replays (times relative to the
// first row). Rows whose x, y (or confidence) are empty or not numbers are skipped and
// counted as malformed (a tracker's lost samples); time must not go backwards. Throws
// std::runtime_error "FILE:LINE: reason" (a missing column names the header's columns).
std::unique_ptr<gaze_source> table_gaze(const std::string& path, const trace_columns& columns, int width, int height);

// UDP datagrams on 127.0.0.1:port, non-blocking (parse_gaze_datagram's formats), mapped by
// the calibration. Throws when the port cannot be bound.
std::unique_ptr<gaze_source> udp_gaze(uint16_t port, int width, int height, const gaze_calibration& calibration = {});

// The mouse pointer, fed by the window (set()).
class mouse_gaze : public gaze_source {
 public:
  mouse_gaze(int width, int height) { width_ = width, height_ = height, x_ = width / 2.0, y_ = height / 2.0; }
  void set(double x, double y) { x_ = x, y_ = y; }
  void read(double now_ms, std::vector<gaze_sample>& out) override { emit(x_, y_, now_ms, out); }
  std::string name() const override { return "mouse"; }

 private:
  double x_, y_;
};

// One datagram, as text; normalised positions (0..1, top-left origin, y down):
//   "X Y"                       version 1 (also "X,Y")
//   "v2 T C EYE X Y"            version 2: T the tracker's time in seconds, C the confidence
//                               0..1, EYE l|r|b (left, right, both); spaces or commas
// Returns "" and fills `out` (x, y normalised; t_s NaN for version 1), or why it is malformed.
struct gaze_datagram {
  double x = 0, y = 0, t_s = std::numeric_limits<double>::quiet_NaN(), confidence = 1;
  gaze_eye eye = gaze_eye::both;
};
std::string parse_gaze_datagram(const std::string& text, gaze_datagram& out);

}  // namespace fov
