// Small, readable charts drawn with OpenCV: axes with ticks and units, series with a
// legend, several panels side by side. Enough for fovbench's three figures.
#pragma once

#include <string>
#include <vector>

namespace fov {

struct plot_series {
  std::string name;
  int colour = 0;  // index into the palette
  std::vector<double> x, y;
  bool lines = true, markers = true;
  std::vector<bool> ringed;  // per point: draw a ring (e.g. on the Pareto front); may be empty
  std::vector<std::string> labels;  // per point: a small text beside it ("" for none); may be empty
  std::vector<double> y_lo, y_hi;   // per point: an error bar from y_lo to y_hi; may be empty
};

struct plot_panel {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  std::vector<plot_series> series;
};

// A panel title that fits `width_px`: the text at the largest font scale from 0.6 down to
// 0.4 whose width fits, shortened in the middle with "..." when even 0.4 is too wide.
struct fitted_title {
  std::string text;
  double scale = 0.6;
  int width_px = 0;
};
fitted_title fit_title(const std::string& title, int width_px);

// Panels side by side, each 720 x 480, legend inside each panel. Written to a temporary
// file, then renamed; throws std::runtime_error naming the path.
void write_plot(const std::vector<plot_panel>& panels, const std::string& path);

}  // namespace fov
