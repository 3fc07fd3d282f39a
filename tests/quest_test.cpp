// QUEST and QUEST+ (apps/fovstair/quest.h): the published algorithms' properties, checked
// against observers that follow each procedure's own model (protocol and session checks
// are in fovstair_test.cpp).
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "fov/random.h"
#include "quest.h"

namespace fov {
namespace {

// A 2AFC observer that is QUEST+'s Weibull (x, t in log10 scale).
double weibull(double x, double t, double beta, double gamma, double lapse) {
  return gamma + (1 - gamma - lapse) * (1 - std::exp(-std::pow(10.0, beta * (x - t))));
}

// The mean and sample SD of estimates.
std::pair<double, double> mean_sd(const std::vector<double>& v) {
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
  double ss = 0;
  for (double e : v) ss += (e - mean) * (e - mean);
  return {mean, std::sqrt(ss / double(v.size() - 1))};
}

TEST(Quest, EpsilonPutsTheCriterionAtTheThreshold) {
  quest_params p;
  const quest q(p, procedure_grid(1, 3, 0.1), true);
  EXPECT_NEAR(q.psi(0), 0.82, 1e-9);  // Psi(x = T) = p_threshold
  EXPECT_NEAR(q.psi(-10), 0.5, 1e-6);  // gamma, the 2AFC guess rate
  EXPECT_NEAR(q.psi(10), 0.01 * 0.5 + 0.99, 1e-9);
  // Watson & Pelli's epsilon for beta 3.5, gamma 0.5, delta 0.01 at 82 %, in closed form.
  EXPECT_NEAR(q.epsilon(), std::log10(-std::log((1 - (0.82 - 0.005) / 0.99) / 0.5)) / 3.5, 1e-9);
}

TEST(Quest, FirstTrialAtTheGuessAndAnswersMoveItTheRightWay) {
  quest_params p;
  p.threshold_guess = 1.7;
  p.guess_sd = 0.2;
  quest q(p, procedure_grid(1, 3, 0.1), true);
  EXPECT_DOUBLE_EQ(q.scale(), 1.7);  // the prior's median, on the grid
  quest yes = q, no = q;
  yes.answer(true);
  no.answer(false);
  EXPECT_LT(yes.scale(), 1.7);  // a correct answer: the threshold is probably lower
  EXPECT_GT(no.scale(), 1.7);
  EXPECT_LT(yes.estimate(), q.estimate());
  EXPECT_GT(no.estimate(), q.estimate());
  const posterior_summary s = q.summary();  // the prior: its interval is +- 1.645 sd (log10)
  EXPECT_NEAR(std::log10(s.hi) - std::log10(s.lo), 2 * 1.645 * 0.2, 0.01);
}

// Watson & Pelli's Weibull with PsychoPy's defaults (beta 3.5, delta 0.01, gamma 0.5), its
// shift epsilon in closed form: P = 0.82 where x = T.
double quest_observer(double x_minus_t) {
  const double beta = 3.5, delta = 0.01, gamma = 0.5, p = 0.82;
  const double epsilon = std::log10(-std::log((1 - (p - delta * gamma) / (1 - delta)) / (1 - gamma))) / beta;
  return delta * gamma + (1 - delta) * (1 - (1 - gamma) * std::exp(-std::pow(10.0, beta * (x_minus_t + epsilon))));
}

// Against an observer that is its own model, QUEST's estimate is unbiased: the mean log
// estimate of 300 series lies within 3 standard errors of the truth.
TEST(Quest, ConvergesOnAnObserverThatIsItsModel) {
  quest_params p;
  p.max_trials = 60;
  p.method = quest_method::mean;
  const double truth = std::log10(1.65);
  std::vector<double> est;
  rng r(7);
  for (int run = 0; run < 300; ++run) {
    quest q(p, procedure_grid(1, 3, 0.05), true);
    while (!q.done()) q.answer(r.uniform() < quest_observer(std::log10(q.scale()) - truth));
    est.push_back(std::log10(q.estimate()));
  }
  const auto [mean, sd] = mean_sd(est);
  EXPECT_LT(std::fabs(mean - truth), 3 * sd / std::sqrt(double(est.size())) + 0.005) << "mean " << mean << " sd " << sd;
  EXPECT_LT(sd, 0.06);  // 60 trials pin the threshold to a few hundredths of a log unit
}

TEST(Quest, StopsWhenTheIntervalIsNarrow) {
  quest_params p;
  p.max_trials = 400;
  p.stop_interval = 0.1;
  quest q(p, procedure_grid(1, 3, 0.1), true);
  rng r(3);
  while (!q.done()) q.answer(r.uniform() < q.psi(std::log10(q.scale()) - std::log10(1.5)));
  EXPECT_LT(q.trials(), 400u);
  const posterior_summary s = q.summary();
  EXPECT_LT(std::log10(s.hi) - std::log10(s.lo), 0.1);
}

// QUEST+ picks the stimulus with the least expected posterior entropy, which is the one
// whose answer carries the most information about the parameters: checked against the
// mutual information computed directly, on a small problem.
TEST(QuestPlus, ChoosesTheMostInformativeStimulus) {
  quest_plus_params p;
  p.thresholds = {1.2, 1.5, 2.4};
  p.slopes = {2, 6};
  const std::vector<double> grid = procedure_grid(1, 3, 0.25);
  quest_plus q(p, grid, true);
  auto h = [](double v) { return v <= 0 || v >= 1 ? 0.0 : -v * std::log(v) - (1 - v) * std::log(1 - v); };
  size_t best = 0;
  double best_info = -1;
  for (size_t k = 0; k < grid.size(); ++k) {
    double mean = 0, noise = 0;  // I(R; theta) = H(R) - E_theta H(R | theta), uniform prior
    for (double t : p.thresholds)
      for (double b : p.slopes) {
        const double v = weibull(std::log10(grid[k]), std::log10(t), b, 0.5, 0.01);
        mean += v / 6, noise += h(v) / 6;
      }
    if (h(mean) - noise > best_info + 1e-12) best_info = h(mean) - noise, best = k;
  }
  EXPECT_DOUBLE_EQ(q.scale(), grid[best]);
}

TEST(QuestPlus, ConvergesOnAnObserverThatIsItsModel) {
  quest_plus_params p;
  p.slopes = {2, 3.5, 6, 10};
  p.max_trials = 60;
  const double truth = std::log10(1.8);
  std::vector<double> est;
  rng r(11);
  const std::vector<double> grid = procedure_grid(1, 3, 0.05);
  for (int run = 0; run < 150; ++run) {
    quest_plus q(p, grid, true);
    while (!q.done()) q.answer(r.uniform() < weibull(std::log10(q.scale()), truth, 6, 0.5, 0.01));
    est.push_back(std::log10(q.estimate()));
  }
  const auto [mean, sd] = mean_sd(est);
  // The threshold grid is the stimulus grid (steps of about 0.012 log units): a bias below
  // one grid step plus 3 standard errors.
  EXPECT_LT(std::fabs(mean - truth), 3 * sd / std::sqrt(double(est.size())) + 0.012) << "mean " << mean << " sd " << sd;
  EXPECT_LT(sd, 0.05);
}

}  // namespace
}  // namespace fov
