#include "quest.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace fov {

namespace {

// The grid index whose log10 scale is nearest `x`.
size_t nearest(const std::vector<double>& log_grid, double x) {
  size_t best = 0;
  for (size_t i = 1; i < log_grid.size(); ++i)
    if (std::fabs(log_grid[i] - x) < std::fabs(log_grid[best] - x)) best = i;
  return best;
}

// The q-quantile of a discrete distribution `w` over ascending `values`, interpolated
// linearly between the midpoints of the cumulative sums (so a single mass gives its value).
double discrete_quantile(const std::vector<double>& values, const std::vector<double>& w, double q) {
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  double before = 0;
  double prev_mid = -1, prev_value = values.front();
  for (size_t i = 0; i < values.size(); ++i) {
    const double mid = (before + w[i] / 2) / total;
    before += w[i];
    if (w[i] <= 0) continue;
    if (mid >= q) {
      if (prev_mid < 0) return values[i];
      return prev_value + (values[i] - prev_value) * (q - prev_mid) / (mid - prev_mid);
    }
    prev_mid = mid, prev_value = values[i];
  }
  return prev_value;
}

double entropy(const double* p, size_t n, double total) {
  double h = 0;
  for (size_t i = 0; i < n; ++i)
    if (p[i] > 0) {
      const double q = p[i] / total;
      h -= q * std::log(q);
    }
  return h;
}

}  // namespace

std::vector<double> procedure_grid(double scale_min, double scale_max, double step) {
  std::vector<double> out;
  const long lo = std::lround(scale_min * 100), hi = std::lround(scale_max * 100), s = std::max(1L, std::lround(step * 100));
  for (long v = lo; v < hi; v += s) out.push_back(v / 100.0);
  out.push_back(hi / 100.0);
  return out;
}

// ---- QUEST ----

quest::quest(const quest_params& p, std::vector<double> grid, bool two_afc) : p_(p), grid_(std::move(grid)) {
  if (grid_.empty()) throw std::invalid_argument("quest: no scales to choose from");
  for (double s : grid_) log_grid_.push_back(std::log10(s));
  gamma_ = p_.gamma >= 0 ? p_.gamma : default_guess_rate(two_afc);
  const double lo = grid_.front(), hi = grid_.back();
  guess_ = std::log10(p_.threshold_guess > 0 ? p_.threshold_guess : std::sqrt(lo * hi));
  const double sd = p_.guess_sd > 0 ? p_.guess_sd : std::log10(hi / lo);
  // epsilon: Psi(epsilon) = p_threshold without it (Psi rises with x), by bisection.
  epsilon_ = 0;
  double a = -p_.range - 10, b = p_.range + 10;
  for (int i = 0; i < 200; ++i) {
    const double m = (a + b) / 2;
    (psi(m) < p_.p_threshold ? a : b) = m;
  }
  epsilon_ = (a + b) / 2;
  half_ = int64_t(std::ceil(p_.range / p_.grain / 2));
  pdf_.resize(size_t(2 * half_ + 1));
  for (size_t i = 0; i < pdf_.size(); ++i) {
    const double z = (t_at(i) - guess_) / sd;
    pdf_[i] = std::exp(-z * z / 2);
  }
  choose();
}

double quest::psi(double x_minus_t) const {
  const double u = std::pow(10.0, std::min(p_.beta * (x_minus_t + epsilon_), 300.0));
  return p_.delta * gamma_ + (1 - p_.delta) * (1 - (1 - gamma_) * std::exp(-u));
}

void quest::answer(bool detected) {
  const double x = std::log10(next_);
  std::vector<double> pdf(pdf_.size());
  double total = 0;
  for (size_t i = 0; i < pdf_.size(); ++i) {
    const double p = psi(x - t_at(i));
    total += pdf[i] = pdf_[i] * (detected ? p : 1 - p);
  }
  // Renormalised every trial so a long series never underflows. An answer no threshold on
  // the grid allows (delta = 0 and a miss far above all of them) leaves the posterior as it was.
  if (total > 0 && std::isfinite(total)) {
    for (double& v : pdf) v /= total;
    pdf_ = std::move(pdf);
  }
  ++trials_;
  choose();
}

double quest::quantile(double q) const {
  std::vector<double> t(pdf_.size());
  for (size_t i = 0; i < t.size(); ++i) t[i] = t_at(i);
  return discrete_quantile(t, pdf_, q);
}

double quest::mean() const {
  double m = 0, total = 0;
  for (size_t i = 0; i < pdf_.size(); ++i) m += t_at(i) * pdf_[i], total += pdf_[i];
  return m / total;
}

void quest::choose() {
  double x = 0;
  switch (p_.method) {
    case quest_method::quantile: x = quantile(0.5); break;
    case quest_method::mean: x = mean(); break;
    case quest_method::mode: x = t_at(size_t(std::max_element(pdf_.begin(), pdf_.end()) - pdf_.begin())); break;
  }
  next_ = grid_[nearest(log_grid_, x)];  // within the range: the grid spans it
}

posterior_summary quest::summary() const {
  return {std::pow(10.0, mean()), std::pow(10.0, quantile(0.05)), std::pow(10.0, quantile(0.95))};
}

double quest::estimate() const { return std::pow(10.0, mean()); }

bool quest::done() const {
  if (trials_ >= p_.max_trials) return true;
  return p_.stop_interval > 0 && trials_ > 0 && quantile(0.95) - quantile(0.05) < p_.stop_interval;
}

// ---- QUEST+ ----

quest_plus::quest_plus(const quest_plus_params& p, std::vector<double> grid, bool two_afc) : p_(p), grid_(std::move(grid)) {
  if (grid_.empty()) throw std::invalid_argument("quest_plus: no scales to choose from");
  if (p_.thresholds.empty()) p_.thresholds = grid_;
  if (p_.lower_asymptotes.empty()) p_.lower_asymptotes = {default_guess_rate(two_afc)};
  auto t = std::make_shared<table>();
  for (double s : p_.thresholds) t->thresholds.push_back(std::log10(s));
  std::sort(t->thresholds.begin(), t->thresholds.end());
  t->stimuli = grid_.size();
  t->params = t->thresholds.size() * p_.slopes.size() * p_.lower_asymptotes.size() * p_.lapse_rates.size();
  if (uint64_t(t->stimuli) * t->params > max_quest_plus_table)
    throw std::invalid_argument("quest_plus: the likelihood table is larger than max_quest_plus_table");
  t->yes.resize(t->stimuli * t->params);
  for (size_t ti = 0; ti < t->thresholds.size(); ++ti)
    for (double beta : p_.slopes)
      for (double g : p_.lower_asymptotes)
        for (double l : p_.lapse_rates) {
          const size_t j = t->threshold.size();
          t->threshold.push_back(t->thresholds[ti]);
          t->threshold_index.push_back(uint32_t(ti));
          for (size_t k = 0; k < t->stimuli; ++k) {
            const double u = std::pow(10.0, std::min(beta * (std::log10(grid_[k]) - t->thresholds[ti]), 300.0));
            t->yes[k * t->params + j] = g + (1 - g - l) * (1 - std::exp(-u));
          }
        }
  table_ = std::move(t);
  post_.assign(table_->params, 1.0 / double(table_->params));
  choose();
}

void quest_plus::choose() {
  // For each stimulus: the posterior after "yes" and after "no", weighted by how likely
  // each answer is; the stimulus with the least expected entropy wins (the first on ties).
  const size_t n = table_->params;
  std::vector<double> yes(n), no(n);
  double best = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < table_->stimuli; ++k) {
    const double* l = &table_->yes[k * n];
    double py = 0, pn = 0;
    for (size_t j = 0; j < n; ++j) {
      yes[j] = post_[j] * l[j], no[j] = post_[j] * (1 - l[j]);
      py += yes[j], pn += no[j];
    }
    const double h = (py > 0 ? py * entropy(yes.data(), n, py) : 0) + (pn > 0 ? pn * entropy(no.data(), n, pn) : 0);
    if (h < best - 1e-12) best = h, next_ = k;
  }
}

void quest_plus::answer(bool detected) {
  const size_t n = table_->params;
  const double* l = &table_->yes[next_ * n];
  std::vector<double> post(n);
  double total = 0;
  for (size_t j = 0; j < n; ++j) total += post[j] = post_[j] * (detected ? l[j] : 1 - l[j]);
  if (total > 0 && std::isfinite(total)) {  // as QUEST's: an impossible answer changes nothing
    for (double& v : post) v /= total;
    post_ = std::move(post);
  }
  ++trials_;
  choose();
}

posterior_summary quest_plus::summary() const {
  std::vector<double> marginal(table_->thresholds.size(), 0.0);
  for (size_t j = 0; j < post_.size(); ++j) marginal[table_->threshold_index[j]] += post_[j];
  double t = 0;
  if (p_.estimate == quest_plus_estimate::mean) {
    for (size_t i = 0; i < marginal.size(); ++i) t += marginal[i] * table_->thresholds[i];
  } else {
    t = table_->threshold[size_t(std::max_element(post_.begin(), post_.end()) - post_.begin())];
  }
  return {std::pow(10.0, t), std::pow(10.0, discrete_quantile(table_->thresholds, marginal, 0.05)),
          std::pow(10.0, discrete_quantile(table_->thresholds, marginal, 0.95))};
}

bool quest_plus::done() const {
  if (trials_ >= p_.max_trials) return true;
  if (p_.stop_interval <= 0 || trials_ == 0) return false;
  const posterior_summary s = summary();
  return std::log10(s.hi) - std::log10(s.lo) < p_.stop_interval;
}

}  // namespace fov
