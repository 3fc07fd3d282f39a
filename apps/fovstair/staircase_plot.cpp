#include "staircase_plot.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "fov/files.h"

namespace fov {

void write_staircase_plot(const std::vector<nlohmann::json>& trials, const std::string& title, double lo, double hi,
                          const std::string& path) {
  const int W = 900, H = 480, left = 70, right = 20, top = 40, bottom = 60;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const int n = std::max<int>(1, int(trials.size()));
  auto px = [&](double i) { return left + int((W - left - right) * (i + 0.5) / n); };
  auto py = [&](double s) { return top + int((H - top - bottom) * (hi - s) / (hi - lo)); };
  const cv::Scalar black(0, 0, 0), grey(160, 160, 160), red(40, 40, 220), blue(200, 90, 30);
  constexpr int font = cv::FONT_HERSHEY_SIMPLEX;
  // Axes, ticks every 0.2 in scale and every 5 trials.
  cv::line(img, {left, top}, {left, H - bottom}, black, 1);
  cv::line(img, {left, H - bottom}, {W - right, H - bottom}, black, 1);
  for (double s = lo; s <= hi + 1e-9; s += 0.2) {
    cv::line(img, {left - 5, py(s)}, {left, py(s)}, black, 1);
    cv::line(img, {left + 1, py(s)}, {W - right, py(s)}, cv::Scalar(235, 235, 235), 1);
    cv::putText(img, fmt::format("{:.1f}", s), {left - 45, py(s) + 5}, font, 0.45, black, 1, cv::LINE_AA);
  }
  for (int i = 0; i < n; i += 5) {
    cv::line(img, {px(i), H - bottom}, {px(i), H - bottom + 5}, black, 1);
    cv::putText(img, std::to_string(i + 1), {px(i) - 6, H - bottom + 22}, font, 0.45, black, 1, cv::LINE_AA);
  }
  cv::putText(img, "trial", {W / 2 - 20, H - 15}, font, 0.55, black, 1, cv::LINE_AA);
  cv::putText(img, "scale s", {5, top - 12}, font, 0.55, black, 1, cv::LINE_AA);
  cv::putText(img, title, {left + 10, 25}, font, 0.6, black, 1, cv::LINE_AA);
  // QUEST / QUEST+: the posterior after each answer, its 5-95 % interval shaded, its
  // estimate a line (catch trials carry none: the last one holds).
  {
    std::vector<cv::Point> upper, lower, estimate;
    for (int i = 0; i < int(trials.size()); ++i) {
      const auto it = trials[size_t(i)].find("estimate");
      if (it == trials[size_t(i)].end() || !it->is_object()) continue;
      const double e = it->value("threshold", 0.0);
      const auto& in = (*it)["interval"];
      if (!in.is_array() || in.size() != 2 || !in[0].is_number() || !in[1].is_number()) continue;
      const double lo_i = std::clamp(in[0].get<double>(), lo, hi), hi_i = std::clamp(in[1].get<double>(), lo, hi);
      upper.push_back({px(i), py(hi_i)}), lower.push_back({px(i), py(lo_i)}), estimate.push_back({px(i), py(std::clamp(e, lo, hi))});
    }
    if (!estimate.empty()) {
      std::vector<cv::Point> band = upper;
      band.insert(band.end(), lower.rbegin(), lower.rend());
      cv::Mat shade = img.clone();
      cv::fillPoly(shade, std::vector<std::vector<cv::Point>>{band}, cv::Scalar(200, 230, 200), cv::LINE_AA);
      cv::addWeighted(shade, 0.6, img, 0.4, 0, img);
      cv::polylines(img, estimate, false, cv::Scalar(40, 140, 40), 2, cv::LINE_AA);
      cv::putText(img, "posterior estimate, 5-95 % shaded", {W - 330, top + 38}, font, 0.45, cv::Scalar(40, 140, 40), 1,
                  cv::LINE_AA);
    }
  }
  // The path of the staircase, then the answers on it.
  cv::Point previous(-1, -1);
  double threshold_sum = 0;
  int thresholds = 0;
  for (int i = 0; i < int(trials.size()); ++i) {
    const auto& t = trials[size_t(i)];
    const cv::Point p(px(i), py(t.value("scale", lo)));
    if (t.value("catch", false)) {
      cv::drawMarker(img, {p.x, H - bottom - 8}, grey, cv::MARKER_TRIANGLE_UP, 8, 1);
      continue;
    }
    if (previous.x >= 0) cv::line(img, previous, p, grey, 1, cv::LINE_AA);
    previous = p;
    const bool detected = t.value("detected", false);
    if (detected) cv::circle(img, p, 5, red, cv::FILLED, cv::LINE_AA);
    else cv::circle(img, p, 5, blue, 2, cv::LINE_AA);
    if (t.value("reversal", false)) cv::circle(img, p, 10, t.value("recorded", false) ? black : grey, 1, cv::LINE_AA);
    if (t.value("recorded", false)) threshold_sum += t.value("threshold", 0.0), ++thresholds;
  }
  if (thresholds > 0) {
    const double mean = threshold_sum / thresholds;
    for (int x = left; x < W - right; x += 12) cv::line(img, {x, py(mean)}, {x + 6, py(mean)}, black, 1);
    cv::putText(img, thresholds == 1 ? fmt::format("threshold: {:.3f}", mean)
                                     : fmt::format("mean of {} thresholds: {:.3f}", thresholds, mean),
                {W - 330, top + 18}, font, 0.5, black, 1, cv::LINE_AA);
  }
  // Legend.
  const int ly = H - 15;
  cv::circle(img, {left + 10, ly - 5}, 5, red, cv::FILLED, cv::LINE_AA);
  cv::putText(img, "detected", {left + 20, ly}, font, 0.45, black, 1, cv::LINE_AA);
  cv::circle(img, {left + 110, ly - 5}, 5, blue, 2, cv::LINE_AA);
  cv::putText(img, "not detected", {left + 120, ly}, font, 0.45, black, 1, cv::LINE_AA);
  cv::circle(img, {W - 300, ly - 5}, 10, black, 1, cv::LINE_AA);
  cv::putText(img, "recorded reversal", {W - 285, ly}, font, 0.45, black, 1, cv::LINE_AA);
  cv::drawMarker(img, {W - 120, ly - 5}, grey, cv::MARKER_TRIANGLE_UP, 8, 1);
  cv::putText(img, "catch", {W - 110, ly}, font, 0.45, black, 1, cv::LINE_AA);
  temp_output temp(path, ".png");  // OpenCV picks the format by the name's extension
  if (!cv::imwrite(temp.temp_path(), img)) throw file_error(fmt::format("{}: cannot write the plot", path));
  temp.commit();
}

void write_psychometric_plot(const psychometric_data& data, const std::vector<psychometric_fit>& fits, const std::string& title,
                             double lo, double hi, const std::string& path) {
  const int W = 900, H = 520, left = 70, right = 20, top = 40, bottom = 90;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  auto px = [&](double s) { return left + int(std::lround((W - left - right) * (s - lo) / (hi - lo))); };
  auto py = [&](double p) { return top + int(std::lround((H - top - bottom) * (1 - p))); };
  const cv::Scalar black(0, 0, 0), light(235, 235, 235);
  const cv::Scalar colours[] = {cv::Scalar(40, 40, 220), cv::Scalar(200, 90, 30), cv::Scalar(40, 150, 40)};
  constexpr int font = cv::FONT_HERSHEY_SIMPLEX;
  cv::line(img, {left, top}, {left, H - bottom}, black, 1);
  cv::line(img, {left, H - bottom}, {W - right, H - bottom}, black, 1);
  for (int i = 0; i <= 10; i += 2) {
    const double p = i / 10.0;
    cv::line(img, {left - 5, py(p)}, {left, py(p)}, black, 1);
    cv::line(img, {left + 1, py(p)}, {W - right, py(p)}, light, 1);
    cv::putText(img, fmt::format("{:.1f}", p), {left - 40, py(p) + 5}, font, 0.45, black, 1, cv::LINE_AA);
  }
  for (double s = lo; s <= hi + 1e-9; s += 0.2) {
    cv::line(img, {px(s), H - bottom}, {px(s), H - bottom + 5}, black, 1);
    cv::putText(img, fmt::format("{:.1f}", s), {px(s) - 12, H - bottom + 22}, font, 0.45, black, 1, cv::LINE_AA);
  }
  cv::putText(img, "scale s", {W / 2 - 150, H - bottom + 45}, font, 0.55, black, 1, cv::LINE_AA);
  cv::putText(img, data.two_afc ? "P(correct)" : "P(detected)", {5, top - 12}, font, 0.55, black, 1, cv::LINE_AA);
  cv::putText(img, title, {left + 110, 25}, font, 0.6, black, 1, cv::LINE_AA);
  uint32_t most = 1;
  for (const psychometric_level& l : data.levels) most = std::max(most, l.n);
  for (const psychometric_level& l : data.levels)
    if (l.n > 0)
      cv::circle(img, {px(l.scale), py(double(l.k) / l.n)}, std::max(2, int(std::lround(10 * std::sqrt(double(l.n) / most)))),
                 cv::Scalar(90, 90, 90), cv::FILLED, cv::LINE_AA);
  for (size_t f = 0; f < fits.size(); ++f) {
    const cv::Scalar c = colours[f % 3];
    std::vector<cv::Point> curve;
    for (int x = px(lo); x <= px(hi); x += 2) {
      const double s = lo + (hi - lo) * (x - left) / double(W - left - right);
      curve.push_back({x, py(psychometric_value(fits[f].family, fits[f].params, s))});
    }
    cv::polylines(img, curve, false, c, 2, cv::LINE_AA);
    const double a = fits[f].params.alpha;
    if (a >= lo && a <= hi) cv::line(img, {px(a), H - bottom}, {px(a), H - bottom - 12}, c, 2);
    const std::string interval = std::isfinite(fits[f].alpha_lo)
                                     ? fmt::format(" [{:.3f}, {:.3f}]", fits[f].alpha_lo, fits[f].alpha_hi)
                                     : std::string();
    cv::putText(img, fmt::format("{}: alpha {:.3f}{}, lapse {:.3f}", label_of(psychometric_family_labels, fits[f].family), a,
                                 interval, fits[f].params.lapse),
                {W / 2 + 40, H - 50 + 16 * int(f)}, font, 0.42, c, 1, cv::LINE_AA);
  }
  temp_output temp(path, ".png");
  if (!cv::imwrite(temp.temp_path(), img)) throw file_error(fmt::format("{}: cannot write the plot", path));
  temp.commit();
}

}  // namespace fov
