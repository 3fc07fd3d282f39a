// Where the viewer is looking, from one of several sources behind one interface.
// Positions are screen pixels; every source clamps to the screen and counts what it clamped.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fov/acuity.h"

namespace fov {

class gaze_source {
 public:
  virtual ~gaze_source() = default;
  // The gaze at `now_ms` (milliseconds since the source started); the last one while the
  // source gives nothing new (silent() tells when that has lasted a while).
  virtual gaze_point poll(double now_ms) = 0;
  virtual std::string name() const = 0;
  virtual bool silent(double now_ms) const { (void)now_ms; return false; }
  uint64_t clamped = 0;    // samples outside the screen, clamped to it
  uint64_t malformed = 0;  // samples that could not be read (skipped)

 protected:
  void clamp_to_screen(double& x, double& y);
  gaze_point clamped_gaze(double x, double y) {  // (x, y) clamped to the screen, counted
    clamp_to_screen(x, y);
    return {x, y};
  }
  int width_ = 0, height_ = 0;
};

// A fixed point (tests, fixation-only experiments).
std::unique_ptr<gaze_source> fixed_gaze(int width, int height, double x, double y);

// A recorded trace, replayed in real time: CSV with the header "t_ms,x,y" (pixels) or
// "t_ms,x_norm,y_norm" (0..1), rows in non-decreasing time. Throws std::runtime_error
// "FILE:LINE: reason" for a bad header, bad numbers or time going backwards. After the
// last row the gaze stays there.
std::unique_ptr<gaze_source> trace_gaze(const std::string& path, int width, int height);

// UDP datagrams "x y" (normalised 0..1, as text) on 127.0.0.1:port, non-blocking; the
// newest datagram wins. Silent after 500 ms without a datagram. Throws when the port
// cannot be bound.
std::unique_ptr<gaze_source> udp_gaze(uint16_t port, int width, int height);

// The mouse pointer, fed by the window (set()).
class mouse_gaze : public gaze_source {
 public:
  mouse_gaze(int width, int height) { width_ = width, height_ = height, x_ = width / 2.0, y_ = height / 2.0; }
  void set(double x, double y) { x_ = x, y_ = y; }
  gaze_point poll(double) override { return clamped_gaze(x_, y_); }
  std::string name() const override { return "mouse"; }

 private:
  double x_, y_;
};

// Parses one datagram "x y" (normalised); false when malformed.
bool parse_gaze_datagram(const std::string& text, double& x, double& y);

}  // namespace fov
