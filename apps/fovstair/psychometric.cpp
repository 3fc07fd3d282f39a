#include "psychometric.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/core/optim.hpp>

#include "fov/random.h"

namespace fov {

namespace {

double core(psychometric_family f, double alpha, double beta, double s) {
  switch (f) {
    case psychometric_family::weibull: return s <= 0 ? 0.0 : 1 - std::exp(-std::pow(s / alpha, beta));
    case psychometric_family::logistic: return 1 / (1 + std::exp(-beta * (s - alpha)));
    case psychometric_family::normal: return 0.5 * std::erfc(-beta * (s - alpha) / std::sqrt(2.0));
  }
  return 0;
}

double logistic(double u) { return 1 / (1 + std::exp(-u)); }
double logit(double v) {
  v = std::clamp(v, 1e-9, 1 - 1e-9);
  return std::log(v / (1 - v));
}

// The free parameters, unconstrained: alpha through a logistic onto [alpha_min, alpha_max],
// beta as its log, the lapse rate through a logistic onto [0, max_lapse].
struct mapping {
  psychometric_family family;
  double guess, max_lapse, alpha_min, alpha_max;
  psychometric_params params(const double* u) const {
    psychometric_params p;
    p.alpha = alpha_min + (alpha_max - alpha_min) * logistic(u[0]);
    p.beta = std::exp(u[1]);
    p.guess = guess;
    p.lapse = max_lapse * logistic(u[2]);
    return p;
  }
  void free(const psychometric_params& p, double* u) const {
    u[0] = logit((p.alpha - alpha_min) / (alpha_max - alpha_min));
    u[1] = std::log(p.beta);
    u[2] = logit(p.lapse / std::max(max_lapse, 1e-12));
  }
};

double negative_log_likelihood(const std::vector<psychometric_level>& levels, psychometric_family f,
                               const psychometric_params& p) {
  double nll = 0;
  for (const psychometric_level& l : levels) {
    const double v = std::clamp(psychometric_value(f, p, l.scale), 1e-12, 1 - 1e-12);
    nll -= double(l.k) * std::log(v) + double(l.n - l.k) * std::log(1 - v);
  }
  return std::isfinite(nll) ? nll : std::numeric_limits<double>::max();
}

class objective : public cv::MinProblemSolver::Function {
 public:
  objective(const std::vector<psychometric_level>& levels, const mapping& m) : levels_(levels), m_(m) {}
  int getDims() const override { return 3; }
  double calc(const double* u) const override { return negative_log_likelihood(levels_, m_.family, m_.params(u)); }

 private:
  const std::vector<psychometric_level>& levels_;
  const mapping& m_;
};

// Nelder-Mead from `start`, restarted once from where it stopped (a simplex can stall).
psychometric_params polish(const std::vector<psychometric_level>& levels, const mapping& m, const psychometric_params& start) {
  cv::Ptr<cv::DownhillSolver> solver = cv::DownhillSolver::create();
  solver->setFunction(cv::makePtr<objective>(levels, m));
  solver->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, 4000, 1e-10));
  double u[3];
  m.free(start, u);
  cv::Mat x(1, 3, CV_64F, u);
  for (int round = 0; round < 2; ++round) {
    const cv::Mat step = (cv::Mat_<double>(1, 3) << 0.3, 0.3, 1.0);
    solver->setInitStep(step);
    solver->minimize(x);
  }
  return m.params(x.ptr<double>());
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double at = q * double(v.size() - 1);
  const size_t i = size_t(at);
  return i + 1 < v.size() ? v[i] + (v[i + 1] - v[i]) * (at - double(i)) : v.back();
}

}  // namespace

double psychometric_value(psychometric_family f, const psychometric_params& p, double scale) {
  return p.guess + (1 - p.guess - p.lapse) * core(f, p.alpha, p.beta, scale);
}

psychometric_fit fit_psychometric(const std::vector<psychometric_level>& levels, psychometric_family family,
                                  const fit_options& o) {
  if (levels.size() < 2) throw std::invalid_argument("a psychometric fit needs trials at two scales or more");
  if (levels.size() > max_psychometric_levels) throw std::invalid_argument("too many levels for a psychometric fit");
  psychometric_fit out;
  out.family = family;
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (const psychometric_level& l : levels) {
    if (!(l.scale > 0) || l.k > l.n) throw std::invalid_argument("a psychometric level needs a positive scale and k <= n");
    lo = std::min(lo, l.scale), hi = std::max(hi, l.scale);
    out.trials += l.n;
  }
  if (out.trials == 0) throw std::invalid_argument("a psychometric fit needs at least one trial");
  const double span = std::max(hi - lo, 1e-3);
  // alpha within the tested range widened by its width each side (and positive): beyond
  // that the data say nothing, and a flat bootstrap fit would put alpha anywhere.
  const mapping m{family, o.guess, o.max_lapse, std::max(lo - span, lo / 10), hi + span};
  out.alpha_min = m.alpha_min, out.alpha_max = m.alpha_max;
  // Starts: alpha across the tested range, slopes from shallow to steep (per log unit for
  // the Weibull, per range for the others), a lapse rate of 2 %.
  psychometric_params best;
  double best_nll = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 10; ++i)
    for (double b : {1.0, 2.0, 4.0, 8.0, 16.0}) {
      psychometric_params p;
      p.alpha = lo + span * i / 10.0;
      p.beta = family == psychometric_family::weibull ? b : b / span;
      p.guess = o.guess, p.lapse = std::min(0.02, o.max_lapse / 2);
      const double nll = negative_log_likelihood(levels, family, p);
      if (nll < best_nll) best_nll = nll, best = p;
    }
  out.params = polish(levels, m, best);
  out.log_likelihood = -negative_log_likelihood(levels, family, out.params);
  for (const psychometric_level& l : levels) {
    const double v = std::clamp(psychometric_value(family, out.params, l.scale), 1e-12, 1 - 1e-12);
    if (l.k > 0) out.deviance += 2 * double(l.k) * std::log(double(l.k) / (double(l.n) * v));
    if (l.n > l.k) out.deviance += 2 * double(l.n - l.k) * std::log(double(l.n - l.k) / (double(l.n) * (1 - v)));
  }
  // Parametric bootstrap (Wichmann & Hill 2001): new answers at the same scales and counts
  // from the fitted function, refitted; alpha's 2.5 and 97.5 percentiles.
  out.alpha_lo = out.alpha_hi = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> alphas;
  rng r(stream_seed(o.seed, uint64_t(family), 0xb007));
  for (uint32_t b = 0; b < o.bootstrap; ++b) {
    std::vector<psychometric_level> sample = levels;
    for (psychometric_level& l : sample) {
      const double v = psychometric_value(family, out.params, l.scale);
      l.k = 0;
      for (uint32_t t = 0; t < l.n; ++t) l.k += r.uniform() < v;
    }
    const psychometric_params p = polish(sample, m, out.params);
    if (std::isfinite(p.alpha) && std::isfinite(p.beta)) alphas.push_back(p.alpha);
  }
  out.bootstrap = uint32_t(alphas.size());
  if (alphas.size() >= 2) out.alpha_lo = percentile(alphas, 0.025), out.alpha_hi = percentile(alphas, 0.975);
  return out;
}

}  // namespace fov
