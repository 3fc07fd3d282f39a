// Pictures fovgen writes: every point of a set, and simple labelled line plots.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fov/pointset.h"

namespace fov {

// Every point as a dot on the canvas (thesis Fig. 12). With a gaze, the screen
// window is outlined, on-screen points are black, off-screen points the renderer
// must still trace are red and unused points grey.
void plot_points(const pointset& set, const std::string& path, std::optional<gaze_point> gaze, uint32_t k_used);

struct plot_series {
  std::string label;
  std::vector<double> x, y;
};

struct line_plot {
  std::string title, x_label, y_label;
  std::vector<plot_series> series;
  int width = 900, height = 600;
};

// Draws axes with ticks and units, one coloured polyline with markers per series and a legend.
void write_line_plot(const line_plot& plot, const std::string& path);

}  // namespace fov
