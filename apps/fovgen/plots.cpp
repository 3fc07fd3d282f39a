#include "plots.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "fov/pointset_io.h"

namespace fov {

namespace {

void write_png(const cv::Mat& image, const std::string& path) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes)) throw file_error(path + ": PNG encoding failed");
  write_file_atomic(path, bytes.data(), bytes.size());
}

// 1, 2 or 5 times a power of ten, giving about `count` ticks over the range.
double nice_step(double range, int count) {
  const double raw = range / std::max(1, count);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) return m * mag;
  return 10 * mag;
}

// Tick text: thousands as "k" and millions as "M" once the step is that coarse.
std::string tick_label(double v, double step) {
  if (step >= 1e6) return fmt::format("{:g}M", v / 1e6);
  if (step >= 1e3) return fmt::format("{:g}k", v / 1e3);
  const int decimals = step >= 1 ? 0 : int(std::ceil(-std::log10(step)));
  return fmt::format("{:.{}f}", v, decimals);
}

}  // namespace

void plot_points(const pointset& set, const std::string& path, std::optional<gaze_point> gaze, uint32_t k_used) {
  if (uint64_t(set.canvas_width()) * set.canvas_height() > (uint64_t(1) << 28))
    throw std::invalid_argument(fmt::format("{}: a {}x{} canvas is too large to plot (limit 2^28 pixels)", path,
                                            set.canvas_width(), set.canvas_height()));
  const int w = int(set.canvas_width()), h = int(set.canvas_height());
  cv::Mat image(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  std::vector<uint8_t> traced;
  canvas_offset o;
  if (gaze) {
    traced = traced_point_mask(set, *gaze, k_used);
    o = offset_for_gaze(set.model.display, *gaze);
  }
  const display_geometry& d = set.model.display;
  for (size_t i = 0; i < set.points.size(); ++i) {
    const point& p = set.points[i];
    cv::Vec3b colour(0, 0, 0);
    if (gaze) {
      colour = on_screen(p, d, o) ? cv::Vec3b(0, 0, 0) : traced[i] ? cv::Vec3b(0, 0, 220) : cv::Vec3b(170, 170, 170);
    }
    image.at<cv::Vec3b>(int(p.y), int(p.x)) = colour;
  }
  if (gaze)
    cv::rectangle(image, cv::Rect(o.x, o.y, d.width, d.height), cv::Scalar(220, 120, 0), 2);
  write_png(image, path);
}

void write_line_plot(const line_plot& plot, const std::string& path) {
  cv::Mat image(plot.height, plot.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 110, right = 30, top = 50, bottom = 70;
  const cv::Rect area(left, top, plot.width - left - right, plot.height - top - bottom);
  double x0 = INFINITY, x1 = -INFINITY, y0 = 0, y1 = -INFINITY;
  for (const plot_series& s : plot.series) {
    for (double v : s.x) x0 = std::min(x0, v), x1 = std::max(x1, v);
    for (double v : s.y) y0 = std::min(y0, v), y1 = std::max(y1, v);
  }
  if (!(x1 > x0)) x1 = x0 + 1;
  if (!(y1 > y0)) y1 = y0 + 1;
  y1 += 0.05 * (y1 - y0);
  auto px = [&](double x) { return area.x + int(std::lround((x - x0) / (x1 - x0) * area.width)); };
  auto py = [&](double y) { return area.y + area.height - int(std::lround((y - y0) / (y1 - y0) * area.height)); };
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  const cv::Scalar ink(40, 40, 40), grid(225, 225, 225);
  const double xs = nice_step(x1 - x0, 8), ys = nice_step(y1 - y0, 6);
  for (double x = std::ceil(x0 / xs) * xs; x <= x1 + 1e-9; x += xs) {
    cv::line(image, {px(x), area.y}, {px(x), area.y + area.height}, grid, 1);
    cv::putText(image, tick_label(x, xs), {px(x) - 14, area.y + area.height + 22}, font, 0.45, ink, 1, cv::LINE_AA);
  }
  for (double y = std::ceil(y0 / ys) * ys; y <= y1 + 1e-9; y += ys) {
    cv::line(image, {area.x, py(y)}, {area.x + area.width, py(y)}, grid, 1);
    const std::string text = tick_label(y, ys);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, font, 0.45, 1, &baseline);
    cv::putText(image, text, {area.x - 8 - size.width, py(y) + 5}, font, 0.45, ink, 1, cv::LINE_AA);
  }
  cv::rectangle(image, area, ink, 1);
  cv::putText(image, plot.title, {left, 30}, font, 0.65, ink, 1, cv::LINE_AA);
  cv::putText(image, plot.x_label, {area.x + area.width / 2 - 80, plot.height - 20}, font, 0.55, ink, 1, cv::LINE_AA);
  cv::Mat ylab(30, 360, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(ylab, plot.y_label, {4, 22}, font, 0.55, ink, 1, cv::LINE_AA);
  cv::rotate(ylab, ylab, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int yh = std::min(ylab.rows, area.height);
  ylab(cv::Rect(0, ylab.rows - yh, ylab.cols, yh)).copyTo(image(cv::Rect(8, area.y + (area.height - yh) / 2, ylab.cols, yh)));
  const cv::Scalar palette[] = {{180, 100, 30}, {40, 40, 200}, {40, 150, 40}, {150, 60, 150}, {20, 140, 200}};
  for (size_t s = 0; s < plot.series.size(); ++s) {
    const plot_series& ser = plot.series[s];
    const cv::Scalar c = palette[s % 5];
    for (size_t i = 0; i < ser.x.size(); ++i) {
      cv::circle(image, {px(ser.x[i]), py(ser.y[i])}, 3, c, cv::FILLED, cv::LINE_AA);
      if (i > 0) cv::line(image, {px(ser.x[i - 1]), py(ser.y[i - 1])}, {px(ser.x[i]), py(ser.y[i])}, c, 2, cv::LINE_AA);
    }
    const int ly = area.y + 20 + 22 * int(s);
    cv::line(image, {area.x + area.width - 220, ly - 5}, {area.x + area.width - 190, ly - 5}, c, 2, cv::LINE_AA);
    cv::putText(image, ser.label, {area.x + area.width - 182, ly}, font, 0.5, ink, 1, cv::LINE_AA);
  }
  write_png(image, path);
}

}  // namespace fov
