#include "fov/rolling.h"

#include <cmath>

#include <fmt/format.h>

#include "fov/labels.h"
#include "fov/stereo.h"

namespace fov {

const char* scanout_name(scanout s) { return label_of(scanout_labels, s); }

std::string validate(const rolling_params& r) {
  if (!(r.frame_period_ms >= min_frame_period_ms && r.frame_period_ms <= max_frame_period_ms))
    return fmt::format("--frame-period must lie in {}..{} ms (got {})", min_frame_period_ms, max_frame_period_ms,
                       r.frame_period_ms);
  if (!(std::fabs(r.start_ms) <= max_camera_time_ms))
    return fmt::format("--camera-time must lie in -{:g}..{:g} ms (got {})", max_camera_time_ms, max_camera_time_ms,
                       r.start_ms);
  if (r.path && r.path->keys.empty()) return "the camera path has no keys";
  if (r.order != scanout::global && !r.path)
    return "--rolling needs --camera: a camera path to move along (a still camera shows every line as the global frame does)";
  return "";
}

namespace {
bool by_columns(scanout s) { return s == scanout::left_right || s == scanout::right_left; }
}  // namespace

double line_time_ms(const rolling_params& r, int line, int width, int height) {
  if (r.order == scanout::global) return 0;
  const bool panel = r.stereo && by_columns(r.order);  // the eyes' columns side by side on one panel
  const int lines = by_columns(r.order) ? (panel ? 2 * width : width) : height;
  if (panel && r.right_eye) line += width;
  const bool reversed = r.order == scanout::bottom_up || r.order == scanout::right_left;
  const int shown = reversed ? lines - 1 - line : line;  // how many lines come before it
  return (shown + 0.5) / lines * r.frame_period_ms;
}

line_cameras rolling_cameras(const rolling_params& r, const camera& base, int width, int height) {
  line_cameras out;
  if (r.order == scanout::global || !r.path) return out;
  out.columns = by_columns(r.order);
  const int lines = out.columns ? width : height;
  out.cameras.reserve(size_t(lines));
  for (int line = 0; line < lines; ++line) {
    const camera head = r.path->at(r.start_ms + line_time_ms(r, line, width, height), base);
    out.cameras.push_back(r.stereo ? eye_camera(head, r.right_eye ? eye_side::right : eye_side::left, r.ipd_mm) : head);
  }
  return out;
}

}  // namespace fov
