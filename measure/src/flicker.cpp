#include "fov/flicker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/gtc/constants.hpp>

#include "fov/metrics.h"

namespace fov {

flicker_report measure_flicker(renderer& r, gaze_point start, const render_params& p, const flicker_params& f) {
  if (f.frames < 2) throw std::invalid_argument("flicker needs at least 2 frames");
  const pointset* set = r.current_set();
  if (!set) throw std::logic_error("measure_flicker: no point set in use");
  const display_geometry& d = set->model.display;
  const camera still = r.cam();
  render_params raw = p, blended = p;
  raw.taa = false;
  blended.taa = true;
  r.reset_history();
  frame previous_raw, previous_taa, previous_ref;
  flicker_report out;
  for (uint32_t n = 0; n < f.frames; ++n) {
    const float yaw = glm::radians(f.yaw_deg_per_frame * float(n));
    const glm::vec3 right = glm::normalize(glm::cross(still.forward, still.up));
    r.cam() = still;
    r.cam().forward = glm::normalize(still.forward * std::cos(yaw) + right * std::sin(yaw));
    const gaze_point g{std::clamp(start.x + f.gaze_px_per_frame * n, 0.0, double(d.width)), start.y};
    frame_timing t;
    const points_trace traced = r.trace(g, raw, t);
    frame now = r.reconstruct(traced.samples, g, raw, t);  // copies: the renderer reuses its frame
    frame now_taa = r.reconstruct(traced.samples, g, blended, t);
    frame now_ref = r.reference(d.width, d.height, raw).image;
    if (n > 0) {
      out.raw += mean_luminance_change(now, previous_raw);
      out.taa += mean_luminance_change(now_taa, previous_taa);
      out.reference += mean_luminance_change(now_ref, previous_ref);
    }
    previous_raw = std::move(now), previous_taa = std::move(now_taa), previous_ref = std::move(now_ref);
  }
  const double pairs = double(f.frames - 1);
  out.raw /= pairs, out.taa /= pairs, out.reference /= pairs;
  r.cam() = still;
  r.reset_history();
  return out;
}

}  // namespace fov
