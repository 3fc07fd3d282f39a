#include "window.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>

#include "fov/colour.h"

namespace fov {

cv::Mat display_image(const frame& f) {
  // sRGB by table: 4096 steps of linear [0, 1] (finer than 8-bit output needs near black
  // only up to 1 code value), in parallel over rows.
  static const std::vector<uint8_t> table = [] {
    std::vector<uint8_t> t(4097);
    for (int i = 0; i <= 4096; ++i) t[size_t(i)] = uint8_t(std::lround(255.0f * srgb_encode(float(i) / 4096.0f)));
    return t;
  }();
  auto byte = [&](float v) { return table[size_t(std::clamp(v, 0.0f, 1.0f) * 4096.0f + 0.5f)]; };
  cv::Mat out(f.height, f.width, CV_8UC3);
  tbb::parallel_for(tbb::blocked_range<int>(0, f.height, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      auto* row = out.ptr<cv::Vec3b>(y);
      const glm::vec3* in = f.rgb.data() + size_t(y) * f.width;
      for (int x = 0; x < f.width; ++x) row[x] = cv::Vec3b(byte(in[x].b), byte(in[x].g), byte(in[x].r));
    }
  });
  return out;
}

view_window::view_window(const std::string& title, int width, int height) : title_(title) {
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
    throw std::runtime_error("no display: DISPLAY is not set (run under X11, or xvfb-run for tests)");
  cv::namedWindow(title_, cv::WINDOW_AUTOSIZE | cv::WINDOW_GUI_NORMAL);
  cv::resizeWindow(title_, width, height);
  cv::setMouseCallback(title_, &view_window::on_mouse, this);
}

view_window::~view_window() { cv::destroyWindow(title_); }

void view_window::on_mouse(int event, int x, int y, int flags, void* self) {
  auto& m = static_cast<view_window*>(self)->mouse_;
  m.x = x + 0.5, m.y = y + 0.5, m.seen = true;
  if (event == cv::EVENT_RBUTTONDOWN) m.right = true, m.last_x = x, m.last_y = y;
  if (event == cv::EVENT_RBUTTONUP) m.right = false;
  if (m.right && (flags & cv::EVENT_FLAG_RBUTTON)) m.drag_x += x - m.last_x, m.drag_y += y - m.last_y, m.last_x = x, m.last_y = y;
}

void view_window::show(const cv::Mat& bgr) { cv::imshow(title_, bgr); }
int view_window::key(int wait_ms) { return cv::waitKeyEx(std::max(1, wait_ms)); }

bool view_window::mouse(double& x, double& y) const {
  if (!mouse_.seen) return false;
  x = mouse_.x, y = mouse_.y;
  return true;
}

bool view_window::right_drag(double& dx, double& dy) {
  dx = mouse_.drag_x, dy = mouse_.drag_y;
  mouse_.drag_x = mouse_.drag_y = 0;
  return dx != 0 || dy != 0;
}

bool view_window::closed() const {
  try {
    return cv::getWindowProperty(title_, cv::WND_PROP_VISIBLE) < 1;
  } catch (const cv::Exception&) {
    return true;
  }
}

void draw_overlay(cv::Mat& bgr, const std::vector<std::string>& lines, gaze_point gaze) {
  if (lines.empty()) return;
  constexpr int font = cv::FONT_HERSHEY_SIMPLEX;
  constexpr double scale = 0.5;
  int width = 0, line_height = 18;
  for (const std::string& l : lines) width = std::max(width, cv::getTextSize(l, font, scale, 1, nullptr).width);
  const int box_w = width + 16, box_h = int(lines.size()) * line_height + 12;
  // The corner farthest from the gaze.
  const bool right = gaze.x < bgr.cols / 2.0, bottom = gaze.y < bgr.rows / 2.0;
  const int x0 = right ? bgr.cols - box_w - 8 : 8, y0 = bottom ? bgr.rows - box_h - 8 : 8;
  const cv::Rect box = cv::Rect(x0, y0, box_w, box_h) & cv::Rect(0, 0, bgr.cols, bgr.rows);
  cv::Mat roi = bgr(box);
  roi.convertTo(roi, -1, 0.35, 0);  // darken behind the text
  for (size_t i = 0; i < lines.size(); ++i)
    cv::putText(bgr, lines[i], {x0 + 8, y0 + 8 + line_height * int(i + 1) - 4}, font, scale, {255, 255, 255}, 1, cv::LINE_AA);
}

void draw_gaze_cursor(cv::Mat& bgr, gaze_point gaze) {
  const cv::Point c{int(gaze.x), int(gaze.y)};
  cv::circle(bgr, c, 9, {0, 0, 0}, 3, cv::LINE_AA);
  cv::circle(bgr, c, 9, {0, 255, 255}, 1, cv::LINE_AA);
}

}  // namespace fov
