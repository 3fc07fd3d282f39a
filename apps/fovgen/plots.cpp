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

}  // namespace fov
