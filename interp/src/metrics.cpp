#include "fov/metrics.h"

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

uint8_t display_byte(float linear) { return uint8_t(std::lround(255 * srgb_encode(linear))); }

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

double pixel_eccentricity_deg(const display_geometry& d, double gaze_x, double gaze_y, int x, int y) {
  const double dist = std::hypot(x + 0.5 - gaze_x, y + 0.5 - gaze_y);
  return std::atan(dist / (double(d.width) * d.viewing_distance)) * 180 / pi;
}

frame_comparison compare_frames(const frame& test, const frame& reference, const display_geometry& display,
                                double gaze_x, double gaze_y) {
  if (test.width != reference.width || test.height != reference.height)
    throw std::invalid_argument("frames differ in size");
  const cv::Mat a = to_display(test), b = to_display(reference);
  cv::Mat ssim_map;
  cv::quality::QualitySSIM::compute(a, b, ssim_map);  // per pixel and channel
  struct sums {
    double squared = 0, ssim = 0;
    uint64_t pixels = 0;
  } all, fovea, mid, periphery;
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x) {
      const cv::Vec3b p = a.at<cv::Vec3b>(y, x), q = b.at<cv::Vec3b>(y, x);
      double se = 0;
      for (int c = 0; c < 3; ++c) se += double(p[c] - q[c]) * double(p[c] - q[c]);
      const cv::Vec3f s = ssim_map.at<cv::Vec3f>(y, x);
      const double ssim = (double(s[0]) + s[1] + s[2]) / 3;
      const double e = pixel_eccentricity_deg(display, gaze_x, gaze_y, x, y);
      sums& band = e < 5 ? fovea : e < 30 ? mid : periphery;
      for (sums* t : {&all, &band}) t->squared += se, t->ssim += ssim, ++t->pixels;
    }
  auto finish = [](const sums& s) {
    band_metrics m;
    m.pixels = s.pixels;
    if (!s.pixels) return m;
    const double mse = s.squared / (3.0 * double(s.pixels));
    m.psnr = mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
    m.ssim = s.ssim / double(s.pixels);
    return m;
  };
  return {finish(all), finish(fovea), finish(mid), finish(periphery)};
}

}  // namespace fov
