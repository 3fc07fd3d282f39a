// A desktop window that shows frames (OpenCV highgui; Qt on Debian), with the mouse
// position and key presses. Frames are drawn 1:1 in screen pixels.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "fov/frame.h"

namespace fov {

// A frame as a display shows it: clamped, sRGB-encoded, 8-bit BGR.
cv::Mat display_image(const frame& f);

// Why no window can open, or "": DISPLAY unset (and no WAYLAND_DISPLAY), malformed, or no
// X server answering at it (tried directly, within two seconds, before the GUI toolkit
// starts: Qt aborts the process when it cannot connect). view_window checks it first.
std::string display_problem();

// How frames reach the screen: `scale` screen pixels per frame pixel (resampled: nearest
// neighbour for whole factors, area-averaged below 1, bilinear otherwise), in a window of
// the scaled size or, `fullscreen`, centred on black in a full-screen window.
struct presentation {
  double scale = 1;
  bool fullscreen = false;
};

class view_window {
 public:
  // Throws std::runtime_error when no display can be opened (no X server). Full screen, a
  // scaled frame larger than the window shows its middle (screen() tells the caller).
  view_window(const std::string& title, int width, int height, presentation how = {});
  ~view_window();
  view_window(const view_window&) = delete;
  view_window& operator=(const view_window&) = delete;

  void show(const cv::Mat& bgr);
  // Waits up to wait_ms (at least 1) for a key; returns it or -1.
  int key(int wait_ms = 1);
  bool mouse(double& x, double& y) const;  // in frame pixels; false until the pointer has entered
  cv::Size screen() const { return screen_; }  // the window's size on screen, pixels
  bool closed() const;                     // the user closed the window
  bool right_drag(double& dx, double& dy);  // movement with the right button held, since the last call

 private:
  std::string title_;
  presentation how_;
  cv::Size frame_, screen_;
  cv::Point offset_;  // where the scaled frame's corner lies in the window
  struct mouse_state {
    double x = 0, y = 0, drag_x = 0, drag_y = 0, last_x = 0, last_y = 0;
    bool seen = false, right = false;
  } mouse_;
  static void on_mouse(int event, int x, int y, int flags, void* self);
};

// Text that fits a width: the lines wrapped at spaces so each is at most `max_width` pixels
// wide in OpenCV's simplex font, at `max_scale` or, where a single word is wider than that,
// at the largest smaller scale (down to 0.3) at which every line fits.
struct fitted_text {
  std::vector<std::string> lines;
  double scale = 0;
  int line_height = 0;  // pixels from one baseline to the next
  int width = 0;        // the widest line, pixels
};
fitted_text fit_text(const std::vector<std::string>& lines, int max_width, double max_scale, int thickness);

// Text lines drawn in a box in the corner of the image farthest from the gaze, so the
// overlay never covers the fovea; wrapped (fit_text) to fit the image's width.
void draw_overlay(cv::Mat& bgr, const std::vector<std::string>& lines, gaze_point gaze);
// Lines on a plain grey screen (instructions, questions, pauses), wrapped to fit its width
// with a margin of an eighth on each side, centred vertically.
cv::Mat message_screen(int width, int height, const std::vector<std::string>& lines);
void draw_gaze_cursor(cv::Mat& bgr, gaze_point gaze);

}  // namespace fov
