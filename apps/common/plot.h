// The tools' figures (fovbench's, fovgen's): panels of series computed in C++, drawn by
// matplotlib (plot.py, embedded at build time, run with Debian's /usr/bin/python3 and
// python3-matplotlib): PNG and SVG, labels placed apart, error bars, one colour per scheme
// in every figure.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fov {

struct plot_series {
  std::string name;
  // The colour key, the same in every figure: nn, shepard, rbf, uniform, full,
  // front-foveated, front-baseline (any other name gets a colour of its own).
  std::string scheme;
  std::string style = "solid";  // line style: solid, dashed, dotted, dashdot
  std::vector<double> x, y;
  bool lines = true, markers = true;
  std::vector<bool> ringed;         // per point: a ring (e.g. on the Pareto front); may be empty
  std::vector<std::string> labels;  // per point: a label beside it ("" for none); may be empty
  std::vector<double> x_lo, x_hi;   // per point: a horizontal error bar; may be empty
  std::vector<double> y_lo, y_hi;   // per point: a vertical error bar; may be empty
};

struct plot_panel {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  std::vector<plot_series> series;
};

// What plot.py reads: the panels (points with a non-finite coordinate left out) and the
// files to write.
nlohmann::json figure_json(const std::vector<plot_panel>& panels, const std::vector<std::string>& outputs);

// Panels side by side, written to STEM.png and STEM.svg (each through a temporary name).
// Returns "" when both were written, else why not in one line (no /usr/bin/python3, no
// matplotlib, the script's first error line): the caller warns and goes on.
std::string write_plot(const std::vector<plot_panel>& panels, const std::string& stem);

}  // namespace fov
