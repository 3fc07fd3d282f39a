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

stair_series::stair_series(const stair_protocol& p)
    : v_(std::in_place_type<staircase>, p.rule, p.scale_min, p.scale_max, p.scale_start) {
  const bool two_afc = p.mode == stair_mode::two_afc;
  const std::vector<double> grid = procedure_grid(p.scale_min, p.scale_max, p.scale_grid);
  if (p.procedure == stair_procedure::quest) v_.emplace<quest>(p.quest, grid, two_afc);
  if (p.procedure == stair_procedure::quest_plus) v_.emplace<quest_plus>(p.quest_plus, grid, two_afc);
}

double stair_series::scale() const {
  return std::visit([](const auto& s) { return s.scale(); }, v_);
}
bool stair_series::done() const {
  return std::visit([](const auto& s) { return s.done(); }, v_);
}
bool stair_series::complete() const {
  if (const auto* s = std::get_if<staircase>(&v_)) return s->complete();
  return done();
}
uint32_t stair_series::trials() const {
  return std::visit([](const auto& s) { return s.trials(); }, v_);
}
const std::vector<double>& stair_series::thresholds() const {
  if (const auto* s = std::get_if<staircase>(&v_)) return s->thresholds();
  return final_;
}

staircase::step stair_series::answer(bool detected) {
  if (auto* s = std::get_if<staircase>(&v_)) return s->answer(detected);
  staircase::step out;
  out.bayesian = true;
  std::visit(
      [&](auto& s) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(s)>, staircase>) {
          s.answer(detected);
          out.posterior = s.summary();
          if (s.done()) {
            out.recorded = true, out.threshold = out.posterior.estimate;
            final_ = {out.threshold};
          }
        }
      },
      v_);
  return out;
}

}  // namespace fov
