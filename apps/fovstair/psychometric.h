// Psychometric functions fitted to a subject's trials by maximum likelihood, with guess
// and lapse rates, and bootstrap confidence intervals (docs/fovstair.md, "Psychometric fits").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fov/labels.h"

namespace fov {

// P(s) = guess + (1 - guess - lapse) F(s), with F:
//   weibull   1 - exp(-(s / alpha)^beta)     alpha: where F = 1 - 1/e (63 %)
//   logistic  1 / (1 + exp(-beta (s - alpha)))  alpha: where F = 1/2
//   normal    Phi(beta (s - alpha))             alpha: where F = 1/2 (beta = 1 / sigma)
enum class psychometric_family : uint8_t { weibull, logistic, normal };
inline constexpr label_table<psychometric_family, 3> psychometric_family_labels = {
    {"weibull", psychometric_family::weibull}, {"logistic", psychometric_family::logistic}, {"normal", psychometric_family::normal}};

// The trials at one scale: n shown, k detected (yes-no) or correct (2AFC).
struct psychometric_level {
  double scale = 1;
  uint32_t n = 0, k = 0;
};

struct psychometric_params {
  double alpha = 1, beta = 1, guess = 0, lapse = 0;
};

double psychometric_value(psychometric_family f, const psychometric_params& p, double scale);

struct fit_options {
  double guess = 0;         // fixed: 0.5 in 2AFC, the false-alarm rate in yes-no
  double max_lapse = 0.06;  // the lapse rate is fitted in [0, max_lapse] (Wichmann & Hill 2001)
  uint32_t bootstrap = 200; // parametric bootstrap samples for alpha's interval (0: none)
  uint64_t seed = 1;
};

struct psychometric_fit {
  psychometric_family family = psychometric_family::weibull;
  psychometric_params params;
  double log_likelihood = 0;
  double deviance = 0;        // against the saturated model (each level's own proportion)
  double alpha_lo = 0, alpha_hi = 0;  // 95 % percentile interval of alpha over the bootstrap (NaN without)
  double alpha_min = 0, alpha_max = 0;  // alpha's bounds: the tested scales widened by their range each side
  // Whether the interval's ends reach alpha's bounds: the data do not bound it on that side.
  bool low_open() const { return alpha_lo <= alpha_min + 1e-3 * (alpha_max - alpha_min); }
  bool high_open() const { return alpha_hi >= alpha_max - 1e-3 * (alpha_max - alpha_min); }
  uint32_t bootstrap = 0;     // samples that converged
  uint32_t trials = 0;
};

// The largest number of levels and of bootstrap samples (a fit stays well under a second).
constexpr size_t max_psychometric_levels = 1000;
constexpr uint32_t max_psychometric_bootstrap = 10000;

// Maximum-likelihood fit (Nelder-Mead, OpenCV's DownhillSolver, from the best of a grid of
// starts), alpha bounded to the tested scales widened by their range on each side. Needs at least two levels and one trial; throws std::invalid_argument otherwise.
psychometric_fit fit_psychometric(const std::vector<psychometric_level>& levels, psychometric_family family,
                                  const fit_options& o);

}  // namespace fov
