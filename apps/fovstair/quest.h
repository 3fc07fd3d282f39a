// The Bayesian adaptive procedures: QUEST (Watson & Pelli 1983) and QUEST+ (Watson 2017),
// on the log10 of the scale factor, choosing among the scales a point set exists for.
// Parameters and defaults follow PsychoPy's QuestHandler and QuestPlusHandler; the
// differences are listed in docs/fovstair.md.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "fov/labels.h"

namespace fov {

enum class quest_method : uint8_t { quantile, mean, mode };
inline constexpr label_table<quest_method, 3> quest_method_labels = {
    {"quantile", quest_method::quantile}, {"mean", quest_method::mean}, {"mode", quest_method::mode}};

// QUEST: one unknown, the threshold T (log10 scale), with a Gaussian prior of sd `guess_sd`
// around log10(threshold_guess) on a grid of `grain` spanning `range`. The observer is
// modelled by the Weibull
//   Psi(x) = delta gamma + (1 - delta) (1 - (1 - gamma) exp(-10^(beta (x - T + epsilon))))
// with epsilon chosen so that Psi = p_threshold at x = T. Each trial shows the scale on the
// grid nearest the posterior's `method` (the median by default), within the scale range.
struct quest_params {
  double threshold_guess = 0;  // scale; 0: the geometric middle of the scale range
  double guess_sd = 0;         // log10 units; 0: log10(max / min), the whole range
  double p_threshold = 0.82, beta = 3.5, delta = 0.01;
  double gamma = -1;           // < 0: 0.5 in 2AFC, 0.01 in yes-no
  double grain = 0.01, range = 5;  // log10 units
  quest_method method = quest_method::quantile;
  uint32_t max_trials = 40;
  double stop_interval = 0;    // stop once the 5-95 % interval of T is narrower (log10 units); 0: off
};

enum class quest_plus_estimate : uint8_t { mean, mode };
inline constexpr label_table<quest_plus_estimate, 2> quest_plus_estimate_labels = {
    {"mean", quest_plus_estimate::mean}, {"mode", quest_plus_estimate::mode}};

// QUEST+: a joint posterior over threshold x slope x lower asymptote x lapse rate of the
// Weibull  Psi(x) = gamma + (1 - gamma - lambda) (1 - exp(-10^(beta (x - T))))  (x, T in
// log10 scale; T is where Psi climbs 63 % of its way), uniform prior. Each trial shows
// the scale on the grid whose answer minimises the expected entropy of the posterior.
struct quest_plus_params {
  std::vector<double> thresholds;        // scales; empty: every scale on the grid
  std::vector<double> slopes{3.5};
  std::vector<double> lower_asymptotes;  // empty: 0.5 in 2AFC, 0.01 in yes-no
  std::vector<double> lapse_rates{0.01};
  quest_plus_estimate estimate = quest_plus_estimate::mean;
  uint32_t max_trials = 40;
  double stop_interval = 0;              // as QUEST's, on the threshold's marginal posterior
};

// The guess rate QUEST's gamma and QUEST+'s lower asymptote default to: 0.5 in 2AFC, 0.01 in yes-no.
inline double default_guess_rate(bool two_afc) { return two_afc ? 0.5 : 0.01; }

// The largest QUEST+ likelihood table (stimuli x parameter combinations): a protocol asking
// for more is refused when it is read, so no trial waits on the entropy search.
constexpr uint64_t max_quest_plus_table = uint64_t(1) << 18;
// The largest QUEST grid (range / grain).
constexpr uint32_t max_quest_grid = 20000;

// Where a Bayesian series stands after an answer: the estimate and its 5-95 % interval (scales).
struct posterior_summary {
  double estimate = 0, lo = 0, hi = 0;
};

class quest {
 public:
  // `grid`: the scales a trial may show, ascending.
  quest(const quest_params& p, std::vector<double> grid, bool two_afc);
  double scale() const { return next_; }
  void answer(bool detected);  // at scale()
  posterior_summary summary() const;
  double estimate() const;      // the final estimate: the posterior mean, as a scale
  bool done() const;
  uint32_t trials() const { return trials_; }
  double epsilon() const { return epsilon_; }
  // Psi at x - T (log10 units), with the protocol's beta, gamma, delta and epsilon.
  double psi(double x_minus_t) const;

 private:
  quest_params p_;
  std::vector<double> grid_, log_grid_;
  double guess_ = 0, epsilon_ = 0, gamma_ = 0.5;
  std::vector<double> pdf_;  // over T = guess_ + (i - half_) grain
  int64_t half_ = 0;
  double next_ = 1;
  uint32_t trials_ = 0;
  double t_at(size_t i) const { return guess_ + double(int64_t(i) - half_) * p_.grain; }
  double quantile(double q) const;
  double mean() const;
  void choose();
};

class quest_plus {
 public:
  quest_plus(const quest_plus_params& p, std::vector<double> grid, bool two_afc);
  double scale() const { return grid_[next_]; }
  void answer(bool detected);
  posterior_summary summary() const;
  double estimate() const { return summary().estimate; }
  bool done() const;
  uint32_t trials() const { return trials_; }
  size_t parameter_combinations() const { return table_->params; }

 private:
  struct table {  // shared by every series of a protocol: P(yes | stimulus k, parameters j)
    size_t stimuli = 0, params = 0;
    std::vector<double> yes;              // stimuli x params
    std::vector<double> threshold;        // per parameter combination, log10
    std::vector<double> thresholds;       // the threshold axis, log10, ascending
    std::vector<uint32_t> threshold_index;
  };
  quest_plus_params p_;
  std::vector<double> grid_;
  std::shared_ptr<const table> table_;
  std::vector<double> post_;
  size_t next_ = 0;
  uint32_t trials_ = 0;
  void choose();
};

// The scales a Bayesian procedure may show: min + i x step (to 0.01) and max.
std::vector<double> procedure_grid(double scale_min, double scale_max, double step);

}  // namespace fov
