// Psychometric fits (apps/fovstair/psychometric.h): maximum likelihood recovers known
// functions, and the bootstrap interval behaves as an interval should.
#include <cmath>

#include <gtest/gtest.h>

#include "fov/random.h"
#include "psychometric.h"

namespace fov {
namespace {

// Trials at 1.0, 1.1, ..., 3.0, `n` each, with the counts the function expects (rounded).
std::vector<psychometric_level> expected_levels(psychometric_family f, const psychometric_params& p, uint32_t n) {
  std::vector<psychometric_level> out;
  for (int i = 0; i <= 20; ++i) {
    psychometric_level l;
    l.scale = 1 + 0.1 * i, l.n = n;
    l.k = uint32_t(std::lround(n * psychometric_value(f, p, l.scale)));
    out.push_back(l);
  }
  return out;
}

TEST(Psychometric, RecoversEachFamilyFromItsExpectedCounts) {
  for (psychometric_family f : {psychometric_family::weibull, psychometric_family::logistic, psychometric_family::normal}) {
    psychometric_params truth;
    truth.alpha = 1.7, truth.guess = 0.5, truth.lapse = 0.03;
    truth.beta = f == psychometric_family::weibull ? 6 : f == psychometric_family::logistic ? 5 : 3;
    fit_options o;
    o.guess = 0.5, o.bootstrap = 0;
    const psychometric_fit fit = fit_psychometric(expected_levels(f, truth, 1000), f, o);
    SCOPED_TRACE(label_of(psychometric_family_labels, f));
    EXPECT_NEAR(fit.params.alpha, 1.7, 0.01);
    EXPECT_NEAR(fit.params.beta, truth.beta, 0.05 * truth.beta);
    EXPECT_NEAR(fit.params.lapse, 0.03, 0.005);
    EXPECT_EQ(fit.params.guess, 0.5);
    EXPECT_LT(fit.deviance, 1.0);  // counts rounded from the curve: nearly the saturated fit
    EXPECT_EQ(fit.trials, 21000u);
  }
}

// On noisy answers the fit is the maximum: no worse than the true parameters, and the lapse
// rate stays in its bounds however the data look.
TEST(Psychometric, IsTheMaximumAndKeepsTheLapseInBounds) {
  psychometric_params truth;
  truth.alpha = 1.6, truth.beta = 4, truth.guess = 0.5, truth.lapse = 0.01;
  rng r(5);
  std::vector<psychometric_level> levels = expected_levels(psychometric_family::weibull, truth, 20);
  for (psychometric_level& l : levels) {
    l.k = 0;
    for (uint32_t t = 0; t < l.n; ++t) l.k += r.uniform() < psychometric_value(psychometric_family::weibull, truth, l.scale);
  }
  levels.back().k = levels.back().n / 2;  // a burst of lapses at the top
  fit_options o;
  o.guess = 0.5, o.bootstrap = 0;
  const psychometric_fit fit = fit_psychometric(levels, psychometric_family::weibull, o);
  double nll_truth = 0;
  for (const auto& l : levels) {
    const double v = psychometric_value(psychometric_family::weibull, truth, l.scale);
    nll_truth -= l.k * std::log(v) + (l.n - l.k) * std::log(1 - v);
  }
  EXPECT_GE(fit.log_likelihood, -nll_truth - 1e-9);
  EXPECT_GE(fit.params.lapse, 0.0);
  EXPECT_LE(fit.params.lapse, 0.06);
}

// The bootstrap interval holds the estimate and narrows about as 1 / sqrt(trials).
TEST(Psychometric, BootstrapIntervalNarrowsWithTrials) {
  psychometric_params truth;
  truth.alpha = 1.7, truth.beta = 5, truth.guess = 0.5, truth.lapse = 0.02;
  fit_options o;
  o.guess = 0.5, o.bootstrap = 200;
  const psychometric_fit few = fit_psychometric(expected_levels(psychometric_family::logistic, truth, 10), psychometric_family::logistic, o);
  const psychometric_fit many = fit_psychometric(expected_levels(psychometric_family::logistic, truth, 160), psychometric_family::logistic, o);
  for (const psychometric_fit& f : {few, many}) {
    EXPECT_LT(f.alpha_lo, f.params.alpha);
    EXPECT_GT(f.alpha_hi, f.params.alpha);
    EXPECT_EQ(f.bootstrap, 200u);
  }
  const double ratio = (few.alpha_hi - few.alpha_lo) / (many.alpha_hi - many.alpha_lo);
  EXPECT_GT(ratio, 2.5);  // 16 x the trials: 4 x narrower expected
  EXPECT_LT(ratio, 6.5);
}

TEST(Psychometric, RefusesTooLittleData) {
  fit_options o;
  EXPECT_THROW(fit_psychometric({{1.5, 10, 5}}, psychometric_family::weibull, o), std::invalid_argument);
  EXPECT_THROW(fit_psychometric({{1.5, 0, 0}, {2, 0, 0}}, psychometric_family::weibull, o), std::invalid_argument);
  EXPECT_THROW(fit_psychometric({{1.5, 3, 4}, {2, 3, 1}}, psychometric_family::weibull, o), std::invalid_argument);
}

}  // namespace
}  // namespace fov
