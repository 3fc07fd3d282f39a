#include "plot.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "fov/files.h"

namespace fov {

namespace {

const cv::Scalar palette[] = {{200, 90, 30}, {40, 40, 220}, {40, 160, 40}, {160, 60, 160},
                              {0, 140, 230}, {120, 120, 0}, {90, 90, 90},  {200, 0, 120}, {0, 200, 200}};
constexpr int font = cv::FONT_HERSHEY_SIMPLEX;

// "Nice" tick values covering [lo, hi].
std::vector<double> ticks(double lo, double hi, bool log) {
  std::vector<double> out;
  if (log) {
    for (double d = std::pow(10, std::floor(std::log10(lo))); d <= hi * 1.0001; d *= 10)
      for (double m : {1.0, 2.0, 5.0})
        if (d * m >= lo * 0.9999 && d * m <= hi * 1.0001) out.push_back(d * m);
    return out;
  }
  const double raw = (hi - lo) / 6, mag = std::pow(10, std::floor(std::log10(raw)));
  const double step = raw / mag < 2 ? 2 * mag : raw / mag < 5 ? 5 * mag : 10 * mag;
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) out.push_back(std::fabs(v) < 1e-12 ? 0 : v);
  return out;
}

std::string tick_text(double v) {
  if (v != 0 && (std::fabs(v) >= 1e4 || std::fabs(v) < 1e-2)) return fmt::format("{:.0e}", v);
  return fmt::format("{:g}", v);
}

}  // namespace

fitted_title fit_title(const std::string& title, int width_px) {
  auto width = [](const std::string& t, double scale) { return cv::getTextSize(t, font, scale, 1, nullptr).width; };
  for (double scale = 0.6; scale > 0.39; scale -= 0.05)
    if (width(title, scale) <= width_px) return {title, scale, width(title, scale)};
  // Still too wide at 0.4: keep n characters, half from each end, around "...".
  std::string t = "...";
  for (size_t n = title.size(); n > 0; --n) {
    t = title.substr(0, n / 2) + "..." + title.substr(title.size() - (n - n / 2));
    if (width(t, 0.4) <= width_px) break;
  }
  return {t, 0.4, width(t, 0.4)};
}

namespace {

void draw_panel(cv::Mat& img, const plot_panel& p, int ox) {
  const int W = 720, H = 480, left = 80, right = 20, top = 40, bottom = 60;
  double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo, ylo = xlo, yhi = -xlo;
  for (const plot_series& s : p.series)
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if ((p.log_x && s.x[i] <= 0) || (p.log_y && s.y[i] <= 0)) continue;
      xlo = std::min(xlo, s.x[i]), xhi = std::max(xhi, s.x[i]), ylo = std::min(ylo, s.y[i]), yhi = std::max(yhi, s.y[i]);
      for (const std::vector<double>* bar : {&s.y_lo, &s.y_hi})
        if (i < bar->size() && std::isfinite((*bar)[i]) && (!p.log_y || (*bar)[i] > 0))
          ylo = std::min(ylo, (*bar)[i]), yhi = std::max(yhi, (*bar)[i]);
    }
  const fitted_title title = fit_title(p.title, W - left - right);
  cv::putText(img, title.text, {ox + left, 25}, font, title.scale, {0, 0, 0}, 1, cv::LINE_AA);
  if (!std::isfinite(xlo)) {
    cv::putText(img, "no data", {ox + W / 2 - 40, H / 2}, font, 0.6, {0, 0, 0}, 1, cv::LINE_AA);
    return;
  }
  auto pad = [](double& lo, double& hi, bool log) {
    if (log) { lo /= 1.3, hi *= 1.3; return; }
    const double span = hi > lo ? hi - lo : std::max(std::fabs(hi), 1.0);
    lo -= 0.06 * span, hi += 0.06 * span;
  };
  pad(xlo, xhi, p.log_x);
  pad(ylo, yhi, p.log_y);
  auto fx = [&](double v) {
    const double t = p.log_x ? (std::log(v) - std::log(xlo)) / (std::log(xhi) - std::log(xlo)) : (v - xlo) / (xhi - xlo);
    return ox + left + int(t * (W - left - right));
  };
  auto fy = [&](double v) {
    const double t = p.log_y ? (std::log(v) - std::log(ylo)) / (std::log(yhi) - std::log(ylo)) : (v - ylo) / (yhi - ylo);
    return H - bottom - int(t * (H - top - bottom));
  };
  const cv::Scalar black(0, 0, 0), grid(230, 230, 230);
  for (double t : ticks(xlo, xhi, p.log_x)) {
    cv::line(img, {fx(t), top}, {fx(t), H - bottom}, grid, 1);
    cv::line(img, {fx(t), H - bottom}, {fx(t), H - bottom + 5}, black, 1);
    const std::string s = tick_text(t);
    cv::putText(img, s, {fx(t) - 4 * int(s.size()), H - bottom + 20}, font, 0.42, black, 1, cv::LINE_AA);
  }
  for (double t : ticks(ylo, yhi, p.log_y)) {
    cv::line(img, {ox + left, fy(t)}, {ox + W - right, fy(t)}, grid, 1);
    cv::line(img, {ox + left - 5, fy(t)}, {ox + left, fy(t)}, black, 1);
    const std::string s = tick_text(t);
    cv::putText(img, s, {ox + left - 10 - 8 * int(s.size()), fy(t) + 5}, font, 0.42, black, 1, cv::LINE_AA);
  }
  cv::rectangle(img, {ox + left, top}, {ox + W - right, H - bottom}, black, 1);
  cv::putText(img, p.x_label, {ox + left + (W - left - right) / 2 - 4 * int(p.x_label.size()), H - 20}, font, 0.5, black, 1,
              cv::LINE_AA);
  // Y label rotated: drawn on a strip, then rotated into place.
  cv::Mat strip(24, H - top - bottom, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(strip, p.y_label, {std::max(0, (strip.cols - 9 * int(p.y_label.size())) / 2), 17}, font, 0.5, black, 1,
              cv::LINE_AA);
  cv::Mat rotated;
  cv::rotate(strip, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
  rotated.copyTo(img(cv::Rect(ox + 4, top, rotated.cols, rotated.rows)));
  int legend_y = top + 18;
  for (const plot_series& s : p.series) {
    const cv::Scalar c = palette[size_t(s.colour) % (sizeof(palette) / sizeof(palette[0]))];
    std::vector<cv::Point> pts;
    std::vector<size_t> index;
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || (p.log_x && s.x[i] <= 0) || (p.log_y && s.y[i] <= 0)) continue;
      pts.push_back({fx(s.x[i]), fy(s.y[i])});
      index.push_back(i);
    }
    if (s.lines && pts.size() > 1) cv::polylines(img, pts, false, c, 2, cv::LINE_AA);
    for (size_t j = 0; j < pts.size(); ++j) {
      const size_t i = index[j];
      if (i < s.y_lo.size() && i < s.y_hi.size() && std::isfinite(s.y_lo[i]) && std::isfinite(s.y_hi[i]) &&
          (!p.log_y || s.y_lo[i] > 0)) {
        const int x = pts[j].x, lo = fy(s.y_lo[i]), hi = fy(s.y_hi[i]);
        cv::line(img, {x, lo}, {x, hi}, c, 1, cv::LINE_AA);
        cv::line(img, {x - 4, lo}, {x + 4, lo}, c, 1, cv::LINE_AA);
        cv::line(img, {x - 4, hi}, {x + 4, hi}, c, 1, cv::LINE_AA);
      }
      if (s.markers) cv::circle(img, pts[j], 4, c, cv::FILLED, cv::LINE_AA);
      if (index[j] < s.ringed.size() && s.ringed[index[j]]) cv::circle(img, pts[j], 8, black, 1, cv::LINE_AA);
      if (index[j] < s.labels.size() && !s.labels[index[j]].empty())
        cv::putText(img, s.labels[index[j]], pts[j] + cv::Point(9, -7), font, 0.36, c * 0.7, 1, cv::LINE_AA);
    }
    if (!s.name.empty()) {
      const int lx = ox + W - right - 250;
      cv::line(img, {lx, legend_y - 4}, {lx + 22, legend_y - 4}, c, 2, cv::LINE_AA);
      if (s.markers) cv::circle(img, {lx + 11, legend_y - 4}, 4, c, cv::FILLED, cv::LINE_AA);
      cv::putText(img, s.name, {lx + 28, legend_y}, font, 0.42, black, 1, cv::LINE_AA);
      legend_y += 17;
    }
  }
}

}  // namespace

void write_plot(const std::vector<plot_panel>& panels, const std::string& path) {
  const int W = 720, H = 480;
  cv::Mat img(H, W * std::max<int>(1, int(panels.size())), CV_8UC3, cv::Scalar(255, 255, 255));
  for (size_t i = 0; i < panels.size(); ++i) draw_panel(img, panels[i], int(i) * W);
  temp_output temp(path, ".png");  // OpenCV picks the format by the name's extension
  if (!cv::imwrite(temp.temp_path(), img)) throw file_error(fmt::format("{}: cannot write the plot", path));
  temp.commit();
}

}  // namespace fov
