#include "fov/speedup.h"

#include <algorithm>
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
  return {summarise(frame_ms), summarise(full_ms), summarise(ratio)};
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
