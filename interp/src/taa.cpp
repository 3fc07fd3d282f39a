#include "fov/taa.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>


namespace fov {

namespace {

constexpr float far_away = 1e7f;  // stands in for +inf depth when reprojecting a direction

glm::vec3 bilinear(const frame& f, float x, float y) {  // x, y in pixel-centre coordinates
  x = std::clamp(x, 0.0f, float(f.width - 1));
  y = std::clamp(y, 0.0f, float(f.height - 1));
  const int x0 = int(x), y0 = int(y);
  const int x1 = std::min(x0 + 1, f.width - 1), y1 = std::min(y0 + 1, f.height - 1);
  const float tx = x - float(x0), ty = y - float(y0);
  auto at = [&](int px, int py) { return f.rgb[size_t(py) * f.width + px]; };
  return glm::mix(glm::mix(at(x0, y0), at(x1, y0), tx), glm::mix(at(x0, y1), at(x1, y1), tx), ty);
}

}  // namespace

frame taa_resolve(taa_state& state, const frame& current, const camera& cam, const display_geometry& display,
                  gaze_point gaze, const taa_params& params) {
  if (current.rgb.size() != size_t(current.width) * current.height || current.depth.size() != current.rgb.size())
    throw std::invalid_argument("TAA needs a frame with colour and depth for every pixel");
  if (!(params.alpha > 0 && params.alpha <= 1)) throw std::invalid_argument("TAA alpha must lie in (0, 1]");
  const bool usable = state.valid && state.history.width == current.width && state.history.height == current.height;
  frame out = current;
  if (usable) {
    const int w = current.width, h = current.height;
    const camera_frame now = make_frame(cam, w, h), before = make_frame(state.cam, w, h);
    // Fast paths (the same result up to float rounding): a still camera reprojects every
    // pixel onto itself, and a
    // still gaze changes no eccentricity.
    const bool still_camera = same_view(cam, state.cam);
    const bool still_gaze = gaze == state.gaze;
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < w; ++x) {
          const size_t i = size_t(y) * w + x;
          // 1. Where this pixel's surface was on the previous frame.
          glm::vec3 hist;
          if (still_camera) {
            hist = state.history.rgb[i];
          } else {
            const glm::vec3 dir = ray_direction(now, float(x) + 0.5f, float(y) + 0.5f);
            const float z = std::isfinite(current.depth[i]) ? current.depth[i] : far_away;
            const glm::vec3 world = now.origin + dir * (z / glm::dot(dir, now.forward));
            float depth_before = 0;
            const glm::vec2 s = project(before, world, &depth_before);
            if (!(depth_before > 0) || s.x < 0 || s.y < 0 || s.x >= float(w) || s.y >= float(h)) continue;
            hist = bilinear(state.history, s.x - 0.5f, s.y - 0.5f);
          }
          // 2. Clip the history towards the current neighbourhood's mean. The moments are of
          // the differences from the current colour c: in a near-flat neighbourhood the plain
          // E[x^2] - E[x]^2 cancels to float noise, whose square root (~1e-3 x) moved the box.
          const glm::vec3 c = current.rgb[i];
          glm::vec3 sum(0), sum2(0);
          int n = 0;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int nx = std::clamp(x + dx, 0, w - 1), ny = std::clamp(y + dy, 0, h - 1);
              const glm::vec3 v = current.rgb[size_t(ny) * w + nx] - c;
              sum += v, sum2 += v * v, ++n;
            }
          const glm::vec3 offset = sum / float(n), mean = c + offset;
          const glm::vec3 sigma = glm::sqrt(glm::max(sum2 / float(n) - offset * offset, glm::vec3(0)));
          // The box mean +- gamma sigma, widened to hold the current colour c; the history is
          // moved along the line towards c until it is inside, so it always lies between
          // the current colour and where it was.
          const glm::vec3 lo = glm::min(mean - params.clip_gamma * sigma, c);
          const glm::vec3 hi = glm::max(mean + params.clip_gamma * sigma, c);
          const glm::vec3 d = hist - c;
          float t = 1;
          for (int ch = 0; ch < 3; ++ch) {
            if (d[ch] > 0) t = std::min(t, (hi[ch] - c[ch]) / d[ch]);
            if (d[ch] < 0) t = std::min(t, (lo[ch] - c[ch]) / d[ch]);
          }
          hist = c + std::max(t, 0.0f) * d;
          // 3. Blend; pixels that moved towards the gaze (focus lag) prefer the current frame.
          const double drop = still_gaze ? 0.0
                                         : pixel_eccentricity_deg(display, state.gaze, x, y) -
                                               pixel_eccentricity_deg(display, gaze, x, y);
          const float lag = params.focus_lag_deg > 0 ? std::clamp(float(drop) / params.focus_lag_deg, 0.0f, 1.0f) : 0;
          const float a = params.alpha + (1 - params.alpha) * lag;
          out.rgb[i] = a * current.rgb[i] + (1 - a) * hist;
        }
    });
  }
  taa_remember(state, out, cam, gaze);
  return out;
}

void taa_remember(taa_state& state, const frame& output, const camera& cam, gaze_point gaze) {
  state.history.width = output.width, state.history.height = output.height;
  state.history.rgb = output.rgb;  // reprojection reads colours only
  state.cam = cam;
  state.gaze = gaze;
  state.valid = true;
  ++state.generation;
}

}  // namespace fov
