#include "staircase.h"

#include <algorithm>
#include <cmath>

namespace fov {

namespace {
double hundredths(double v) { return std::round(v * 100) / 100; }
}  // namespace

staircase::staircase(const stair_rule& rule, double scale_min, double scale_max, double start)
    : rule_(rule), min_(scale_min), max_(scale_max), scale_(hundredths(start)) {
  if (scale_ >= max_) direction_ = -1;  // a start at the top descends
}

staircase::step staircase::answer(bool detected) {
  step out;
  ++trials_;
  int move = 0;  // +1 up (thin the set further), -1 down
  if (detected) {
    run_missed_ = 0;
    if (++run_detected_ >= rule_.down) move = -1, run_detected_ = 0;
  } else {
    run_detected_ = 0;
    if (++run_missed_ >= rule_.up) move = +1, run_missed_ = 0;
  }
  if (move == 0) return out;
  if (move != direction_) {
    out.reversal = true;
    out.threshold = scale_;
    direction_ = move;
    if (++reversals_ > rule_.discard_reversals) {
      out.recorded = true;
      thresholds_.push_back(scale_);
    }
  }
  const double size = reversals_ == 0 ? rule_.initial_step : rule_.step;
  scale_ = hundredths(std::clamp(scale_ + move * size, min_, max_));
  return out;
}

}  // namespace fov
