// Rolling display time (issue 28): a display that shows its lines one after another, so each
// line is seen at its own instant. Rendering each line from where the camera is at that
// instant removes the staleness a frame rendered at one instant shows at the lines shown last
// (Perceptual Rasterization, ../shared/papers/perceptual-rasterization.txt).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include "fov/camera.h"
#include "fov/trace.h"

namespace fov {

// The order a display shows its lines in.
enum class scanout : uint8_t {
  global,      // every pixel at once, at the frame's start (what fovray always rendered)
  top_down,    // rows, the top one first
  bottom_up,   // rows, the bottom one first
  left_right,  // columns, the left one first (a panel mounted on its side)
  right_left,  // columns, the right one first
};
inline constexpr std::pair<const char*, scanout> scanout_labels[] = {{"global", scanout::global},
                                                                    {"top-down", scanout::top_down},
                                                                    {"bottom-up", scanout::bottom_up},
                                                                    {"left-right", scanout::left_right},
                                                                    {"right-left", scanout::right_left}};
const char* scanout_name(scanout s);  // its label

// The documented range of a frame period (milliseconds): 1000 Hz to 1 Hz.
constexpr double min_frame_period_ms = 1, max_frame_period_ms = 1000;
// The documented range of a time on a camera path (milliseconds, either sign).
constexpr double max_camera_time_ms = 1e12;

struct rolling_params {
  scanout order = scanout::global;
  // The time the scanout takes, first line to last: a display refreshing at f Hz without
  // blanking scans for 1000 / f ms (90 Hz: 11.1 ms).
  double frame_period_ms = 1000.0 / 90;
  // Where the camera moves: a camera path, and the time on it (ms) when the frame's scanout
  // begins. Without a path the camera is still during a frame, and every order gives the
  // global frame. The tools' --camera FILE and --camera-time set them.
  std::shared_ptr<const camera_path> path;
  double start_ms = 0;
  // With two eyes (fov/stereo.h; the stereo renderer sets these per eye): the screen is one
  // half of a panel that shows the eyes side by side and scans them out as one, as the FOVE 0
  // does. A row scanout shows both eyes' row at once; a column scanout crosses the left eye's
  // columns and then the right eye's (right-left: the other way), each eye in half the
  // period. Each line's camera is this eye's: the path's head camera moved ipd_mm / 2000 to
  // the eye's side (fov::eye_camera).
  bool stereo = false;
  bool right_eye = false;
  double ipd_mm = 0;
};
// "" when the params are valid, else the reason naming the flag (--frame-period, --camera-time).
std::string validate(const rolling_params& r);

// The time (ms after the scanout begins) at which screen line `line` (a row counted from the
// top, or a column from the left, as the order scans) is shown: the middle of its share of
// the period, (k + 0.5) / lines x period for the k-th line shown; 0 for global. With stereo,
// a column's line is counted on the panel (the right eye's after the left eye's width).
double line_time_ms(const rolling_params& r, int line, int width, int height);

// The cameras of a rolling frame on a width x height screen: each line's camera on the path
// at start_ms + line_time_ms, `base` giving the field of view and up (camera_path::at), with
// stereo moved to the eye. Empty for global or without a path: the frame's one camera then is
// the path's at start_ms (the eye's, placed by the stereo renderer).
line_cameras rolling_cameras(const rolling_params& r, const camera& base, int width, int height);

}  // namespace fov
