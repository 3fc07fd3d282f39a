#include "fov/metrics.h"

#include "fov/bands.h"

#include "fov/colour.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/quality/qualityssim.hpp>

namespace fov {

namespace {

constexpr double pi = 3.14159265358979323846;

cv::Mat to_display(const frame& f) {
  cv::Mat m(f.height, f.width, CV_8UC3);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const glm::vec3& c = f.rgb[size_t(y) * f.width + x];
      m.at<cv::Vec3b>(y, x) = {display_byte(c.r), display_byte(c.g), display_byte(c.b)};
    }
  return m;
}

}  // namespace

double acuity_weight(const spacing_model& eye, double e) {
  const double fd = display_nyquist_cpd(eye.display);
  return std::min(cutoff_frequency_cpd(eye.acuity, e), fd) / fd;
}

namespace {

struct sums {
  double squared = 0, ssim = 0;
  uint64_t pixels = 0;
};

band_metrics finish(const sums& s) {
  band_metrics m;
  m.pixels = s.pixels;
  if (!s.pixels) return m;
  const double mse = s.squared / (3.0 * double(s.pixels));
  m.psnr = mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
  m.ssim = s.ssim / double(s.pixels);
  return m;
}

}  // namespace

error_report measure_error(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                           const std::vector<double>& edges, double bin_deg) {
  if (test.width != reference.width || test.height != reference.height)
    throw std::invalid_argument("frames differ in size");
  if (!(bin_deg > 0)) throw std::invalid_argument("bin width must be positive");
  const eccentricity_bands bands_of(eye.display, gaze, edges);
  const cv::Mat a = to_display(test), b = to_display(reference);
  cv::Mat ssim_map;
  cv::quality::QualitySSIM::compute(a, b, ssim_map);  // per pixel and channel
  error_report r;
  r.edges_deg = edges;
  r.bin_deg = bin_deg;
  sums all;
  std::vector<sums> bands(bands_of.count());
  std::vector<double> bin_squared;
  double weighted = 0, weights = 0;
  // The weight depends on eccentricity only: tabulated per 0.01 degree.
  std::vector<double> weight_table(9001);
  for (size_t i = 0; i < weight_table.size(); ++i) weight_table[i] = acuity_weight(eye, double(i) * 0.01);
  bands_of.for_each_pixel(test.width, test.height, [&](int x, int y, double e, size_t band) {
      const cv::Vec3b p = a.at<cv::Vec3b>(y, x), q = b.at<cv::Vec3b>(y, x);
      double se = 0;
      for (int c = 0; c < 3; ++c) se += double(p[c] - q[c]) * double(p[c] - q[c]);
      const cv::Vec3f s = ssim_map.at<cv::Vec3f>(y, x);
      const double ssim = (double(s[0]) + s[1] + s[2]) / 3;
      for (sums* t : {&all, &bands[band]}) t->squared += se, t->ssim += ssim, ++t->pixels;
      const double unit = se / (3.0 * 255.0 * 255.0);  // squared error in full-scale units, mean over RGB
      const double w = weight_table[std::min(weight_table.size() - 1, size_t(e * 100 + 0.5))];
      weighted += w * unit, weights += w;
      const size_t bin = size_t(e / bin_deg);
      if (bin >= bin_squared.size()) bin_squared.resize(bin + 1, 0.0), r.profile_pixels.resize(bin + 1, 0);
      bin_squared[bin] += unit, ++r.profile_pixels[bin];
    });
  r.overall = finish(all);
  for (const sums& s : bands) r.bands.push_back(finish(s));
  r.foveated_error = weights > 0 ? std::sqrt(weighted / weights) : 0;
  r.foveated_psnr = r.foveated_error > 0 ? 20 * std::log10(1 / r.foveated_error) : std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < bin_squared.size(); ++i)
    r.profile_rmse.push_back(r.profile_pixels[i] ? std::sqrt(bin_squared[i] / double(r.profile_pixels[i])) : 0.0);
  return r;
}

std::vector<double> geometry_coverage(const frame& f, const display_geometry& d, gaze_point gaze,
                                      const std::vector<double>& edges) {
  const eccentricity_bands bands(d, gaze, edges);
  if (f.depth.size() != size_t(f.width) * size_t(f.height) || f.rgb.size() != f.depth.size())
    return std::vector<double>(bands.count(), std::numeric_limits<double>::quiet_NaN());
  std::vector<double> hits(bands.count(), 0), all(bands.count(), 0);
  bands.for_each_pixel(f.width, f.height, [&](int x, int y, double, size_t b) {
    ++all[b];
    hits[b] += std::isfinite(f.depth[size_t(y) * f.width + x]) ? 1 : 0;
  });
  std::vector<double> out;
  for (size_t b = 0; b < all.size(); ++b) out.push_back(all[b] > 0 ? hits[b] / all[b] : std::numeric_limits<double>::quiet_NaN());
  return out;
}

double mean_luminance_change(const frame& a, const frame& b) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size())
    throw std::invalid_argument("frames differ in size");
  if (a.rgb.empty()) return 0;
  auto luma = [](const glm::vec3& c) {
    auto e = [](float v) { return double(srgb_encode(std::clamp(v, 0.0f, 1.0f))); };
    return 0.2126 * e(c.r) + 0.7152 * e(c.g) + 0.0722 * e(c.b);
  };
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) sum += std::fabs(luma(a.rgb[i]) - luma(b.rgb[i]));
  return sum / double(a.rgb.size());
}

}  // namespace fov
