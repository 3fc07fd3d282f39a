// The check of fovray's FovVideoVDP (measure/fvvdp.h) against values of the published
// implementation: `fovbench validate-jod DIR` and the test that holds every value within
// 0.1 JOD. DIR is ../shared/metric-validation or a folder laid out like it: a
// jod-reference.json (its display geometry, one row per pair) beside the images.
#pragma once

#include <string>
#include <vector>

namespace fov {

// One published value and ours. `view`: nonfoveated, foveated_centre (gaze at the screen's
// centre) or foveated_corner (gaze at (48, 48), the folder's README).
struct jod_check {
  std::string test, reference, view;
  double published = 0, ours = 0;
};
struct jod_validation {
  std::vector<jod_check> rows;
  double worst = 0;  // the largest |ours - published|
};

// Reads DIR/jod-reference.json and every image it names, and computes each row's values.
// Image rows are pairs; a video row's test reads "PATH-NN.png (frames A-B, F fps)" (NN the
// frame number, two digits) against a still reference "PATH.png (static)". Throws
// file_error naming the file for anything unreadable or not in that layout.
jod_validation validate_jod(const std::string& dir);

// A Markdown table: test, view, published, fovray, difference; then the worst difference.
std::string jod_validation_markdown(const jod_validation& v);

}  // namespace fov
