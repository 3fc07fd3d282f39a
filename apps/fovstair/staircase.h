// One condition's series: the transformed up-down rule of stair_rule on the scale factor
// (staircase), or QUEST / QUEST+ (quest.h), behind one interface (stair_series).
#pragma once

#include <cstdint>
#include <variant>
#include <vector>

#include "protocol.h"
#include "quest.h"

namespace fov {

class staircase {
 public:
  staircase(const stair_rule& rule, double scale_min, double scale_max, double start);

  double scale() const { return scale_; }  // the scale to show next
  bool done() const { return thresholds_.size() >= rule_.thresholds || trials_ >= rule_.max_trials; }
  bool complete() const { return thresholds_.size() >= rule_.thresholds; }

  // What one answer did to the series.
  struct step {
    bool reversal = false;  // the direction turned
    bool recorded = false;  // ... and gave a threshold (not among the discarded reversals)
    double threshold = 0;   // the scale at that reversal
    bool bayesian = false;  // QUEST or QUEST+: `posterior` holds the estimate after this answer
    posterior_summary posterior;
  };
  // Records the answer at scale(): `detected` is "noticed something" (yes-no) or a
  // correct pick (2AFC). Moves the scale when a run of answers completes.
  step answer(bool detected);

  const std::vector<double>& thresholds() const { return thresholds_; }
  uint32_t trials() const { return trials_; }
  uint32_t reversals() const { return reversals_; }
  int direction() const { return direction_; }  // +1 ascending, -1 descending

 private:
  stair_rule rule_;
  double min_, max_, scale_;
  int direction_ = +1;  // the thesis starts ascending; a start at scale_max descends
  uint32_t run_detected_ = 0, run_missed_ = 0, trials_ = 0, reversals_ = 0;
  std::vector<double> thresholds_;
};

// A series under the protocol's procedure. For QUEST and QUEST+ the series records one
// threshold, the final estimate, on its last trial.
class stair_series {
 public:
  explicit stair_series(const stair_protocol& p);
  double scale() const;
  bool done() const;
  bool complete() const;  // up-down: all thresholds recorded; Bayesian: done (either stopping rule)
  staircase::step answer(bool detected);
  const std::vector<double>& thresholds() const;
  uint32_t trials() const;

 private:
  std::variant<staircase, quest, quest_plus> v_;
  std::vector<double> final_;
};

}  // namespace fov
