#include "fov/detail_noise.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "fov/random.h"

namespace fov {

std::string validate(const detail_noise_params& p) {
  if (!(p.gain >= 0 && p.gain <= 4)) return fmt::format("--detail-noise must lie in 0..4 (got {})", p.gain);
  if (!(p.from_deg >= 0 && p.from_deg <= 90))
    return fmt::format("--detail-noise-from must lie in 0..90 degrees (got {})", p.from_deg);
  if (!(p.ramp_deg >= 0 && p.ramp_deg <= 90))
    return fmt::format("--detail-noise-ramp must lie in 0..90 degrees (got {})", p.ramp_deg);
  return "";
}

float detail_noise_gain(const detail_noise_params& p, double eccentricity_deg) {
  if (eccentricity_deg < p.from_deg) return 0;
  if (p.ramp_deg <= 0) return p.gain;
  return p.gain * float(std::min(1.0, (eccentricity_deg - p.from_deg) / p.ramp_deg));
}

void add_detail_noise(frame& image, const frame& spread, const display_geometry& display, gaze_point gaze,
                      const detail_noise_params& p, uint64_t seed) {
  if (image.width != spread.width || image.height != spread.height || image.width != display.width ||
      image.height != display.height || spread.rgb.size() != image.rgb.size())
    throw std::invalid_argument("add_detail_noise: the frame, its spread and the display differ in size");
  if (!p.enabled()) return;
  const int w = image.width;
  // Where the gain starts and where it is full, as squared distances from the gaze in
  // pixels (pixel_eccentricity_deg inverted): the arc tangent is taken inside the ramp only.
  const double px_per_tan = double(w) * display.viewing_distance, to_rad = 3.14159265358979323846 / 180;
  auto squared_px = [&](double deg) {
    const double r = deg >= 90 ? 1e300 : std::tan(deg * to_rad) * px_per_tan;
    return r * r;
  };
  const double start2 = squared_px(p.from_deg), full2 = squared_px(p.from_deg + p.ramp_deg);
  const uint64_t base = stream_seed(seed, 0x64657461696cull);
  tbb::parallel_for(0, image.height, [&](int y) {
    const double dy = y + 0.5 - gaze.y;
    for (int x = 0; x < w; ++x) {
      const double dx = x + 0.5 - gaze.x, d2 = dx * dx + dy * dy;
      if (d2 < start2) continue;
      const float g = d2 >= full2 ? p.gain : detail_noise_gain(p, std::atan(std::sqrt(d2) / px_per_tan) / to_rad);
      if (g == 0) continue;
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      // A standard normal number, near enough: four 16-bit uniforms summed (Irwin-Hall),
      // centred and scaled to unit variance, from one splitmix64 draw of the pixel's state.
      uint64_t state = base + uint64_t(i) * 0x9e3779b97f4a7c15ull;
      const uint64_t bits = splitmix64(state);
      const float sum = float((bits & 0xFFFF) + ((bits >> 16) & 0xFFFF) + ((bits >> 32) & 0xFFFF) + (bits >> 48)) +
                        2.0f;  // each uniform at its 16-bit cell's centre
      const float n = (sum * (1.0f / 65536.0f) - 2.0f) * 1.7320508f;
      image.rgb[i] = glm::max(glm::vec3(0), image.rgb[i] + (g * n) * spread.rgb[i]);
    }
  });
}

}  // namespace fov
