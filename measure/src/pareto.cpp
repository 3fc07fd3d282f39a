#include "fov/pareto.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fov {

std::vector<size_t> pareto_front(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<size_t> order;
  for (size_t i = 0; i < x.size() && i < y.size(); ++i)
    if (std::isfinite(x[i]) && !std::isnan(y[i])) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return x[a] != x[b] ? x[a] < x[b] : y[a] < y[b]; });
  std::vector<size_t> front;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i : order)
    if (y[i] < best) front.push_back(i), best = y[i];
  return front;
}

double time_at_error(const std::vector<std::pair<double, double>>& front, double error) {
  // The front sorted by time has falling error; between two of its points the time needed
  // for an error is interpolated in log time.
  std::vector<std::pair<double, double>> f = front;
  std::sort(f.begin(), f.end());
  for (size_t i = 0; i < f.size(); ++i) {
    if (f[i].second == error) return f[i].first;
    if (i + 1 < f.size() && f[i].second > error && f[i + 1].second < error) {
      const double t = (f[i].second - error) / (f[i].second - f[i + 1].second);
      return std::exp((1 - t) * std::log(f[i].first) + t * std::log(f[i + 1].first));
    }
  }
  return std::nan("");
}

double equal_error_speedup(const std::vector<std::pair<double, double>>& foveated,
                           const std::vector<std::pair<double, double>>& baseline, double error) {
  return time_at_error(baseline, error) / time_at_error(foveated, error);
}

}  // namespace fov
