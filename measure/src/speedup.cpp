#include "fov/speedup.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <random>
#include <stdexcept>

namespace fov {

timing summarise(std::vector<double> v) {
  if (v.empty()) throw std::invalid_argument("no measurements to summarise");
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return {n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]), v.front(), v.back()};
}

paired_timing pair_timings(const std::vector<double>& frame_ms, const std::vector<double>& full_ms) {
  if (frame_ms.empty() || frame_ms.size() != full_ms.size()) throw std::invalid_argument("unpaired timings");
  std::vector<double> ratio;
  for (size_t i = 0; i < frame_ms.size(); ++i) ratio.push_back(full_ms[i] / frame_ms[i]);
  return {summarise(frame_ms), summarise(full_ms), summarise(ratio), ratio};
}

namespace {

double median_of(std::vector<double>& v) {
  const size_t n = v.size(), h = n / 2;
  std::nth_element(v.begin(), v.begin() + long(h), v.end());
  if (n % 2) return v[h];
  const double upper = v[h];
  return 0.5 * (*std::max_element(v.begin(), v.begin() + long(h)) + upper);
}

}  // namespace

speedup_interval chained_speedup(const std::vector<double>& paired, const std::vector<double>& ladder, double level,
                                 uint32_t resamples, uint64_t seed) {
  if (paired.empty()) return {NAN, NAN, NAN};
  const std::vector<double> rungs = ladder.empty() ? std::vector<double>{1.0} : ladder;
  auto estimate = [](std::vector<double> a, std::vector<double> b) { return median_of(a) * median_of(b); };
  speedup_interval out;
  out.estimate = estimate(paired, rungs);
  std::mt19937_64 random(seed);
  std::vector<double> products, a(paired.size()), b(rungs.size());
  std::uniform_int_distribution<size_t> pick_a(0, paired.size() - 1), pick_b(0, rungs.size() - 1);
  for (uint32_t i = 0; i < std::max(resamples, 1u); ++i) {
    for (double& x : a) x = paired[pick_a(random)];
    for (double& x : b) x = rungs[pick_b(random)];
    products.push_back(estimate(a, b));
  }
  std::sort(products.begin(), products.end());
  const double tail = (1 - level) / 2;
  auto at = [&](double q) { return products[std::min(products.size() - 1, size_t(q * double(products.size())))]; };
  out.lo = at(tail), out.hi = at(1 - tail);
  return out;
}

double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

paired_timing measure_speedup(renderer& r, gaze_point gaze, const render_params& p, int width, int height, uint32_t repeats) {
  if (repeats < 1) throw std::invalid_argument("at least one repetition");
  std::vector<double> frame_ms, full_ms;
  for (uint32_t i = 0; i < repeats; ++i) {
    frame_timing full, fov;
    r.reference(width, height, p, &full);
    r.foveated(gaze, p, &fov);
    full_ms.push_back(full.total_ms());
    frame_ms.push_back(fov.total_ms());
  }
  return pair_timings(frame_ms, full_ms);
}

}  // namespace fov
