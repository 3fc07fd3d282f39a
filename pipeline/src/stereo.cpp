#include "fov/stereo.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace fov {

std::string validate(const stereo_params& p) {
  if (!(p.ipd_mm >= 0 && p.ipd_mm <= max_ipd_mm))
    return fmt::format("--ipd must lie in 0..{} mm (got {})", max_ipd_mm, p.ipd_mm);
  return "";
}

camera eye_camera(const camera& head, eye_side e, double ipd_mm) {
  const camera_frame f = make_frame(head, 2, 2);  // only its axes are read
  const float half = float(ipd_mm / 2000.0);
  camera c = head;
  c.position += (e == eye_side::left ? -half : half) * f.right;
  return c;
}

reuse_history history_of(const point_samples& samples, const camera& cam, const pointset& set, uint32_t spp) {
  const display_geometry& d = set.model.display;
  const size_t n = set.points.size();
  if (samples.colour.size() != n || samples.depth.size() != n || samples.hits.size() != n)
    throw std::invalid_argument("history_of: the samples belong to another set");
  reuse_history h;
  h.reset(n);
  h.view = make_frame(cam, d.width, d.height);
  h.offset = samples.offset;
  h.mirror_x = samples.mirror_x, h.mirror_y = samples.mirror_y;
  for (const uint32_t i : samples.traced) {
    if (i >= n) throw std::invalid_argument("history_of: a traced point beyond the set");
    const glm::vec2 at = placed_position(d, set.points[i], samples.offset, samples.mirror_x, samples.mirror_y);
    const glm::vec3 dir = ray_direction(h.view, at.x, at.y);
    h.colour[i] = samples.colour[i];
    h.hits[i] = samples.hits[i];
    if (samples.hits[i] == 0) {
      h.kind[i] = reuse_history::seen::miss;
      h.where[i] = dir;
    } else if (samples.hits[i] == spp && std::isfinite(samples.depth[i])) {
      h.kind[i] = reuse_history::seen::hit;
      h.where[i] = h.view.origin + dir * (samples.depth[i] / glm::dot(dir, h.view.forward));
    } else {
      h.kind[i] = reuse_history::seen::mixed;
    }
  }
  h.valid = true;
  return h;
}

frame side_by_side(const frame& left, const frame& right) {
  if (left.width != right.width || left.height != right.height)
    throw std::invalid_argument(fmt::format("side_by_side: the eyes' frames differ in size ({}x{} and {}x{})", left.width,
                                            left.height, right.width, right.height));
  frame out;
  out.width = 2 * left.width, out.height = left.height;
  out.rgb.resize(size_t(out.width) * out.height);
  out.depth.resize(out.rgb.size());
  const size_t w = size_t(left.width);
  for (int y = 0; y < left.height; ++y)
    for (int e = 0; e < 2; ++e) {
      const frame& f = e ? right : left;
      const size_t from = size_t(y) * w, to = size_t(y) * out.width + e * w;
      std::copy_n(f.rgb.begin() + from, w, out.rgb.begin() + to);
      if (f.depth.size() == f.rgb.size())
        std::copy_n(f.depth.begin() + from, w, out.depth.begin() + to);
      else
        std::fill_n(out.depth.begin() + to, w, std::numeric_limits<float>::infinity());
    }
  out.rays = left.rays + right.rays;
  return out;
}

frame eye_half(const frame& both, eye_side e) {
  if (both.width % 2 != 0 || both.rgb.size() != size_t(both.width) * both.height)
    throw std::invalid_argument(fmt::format("eye_half: a {}x{} frame is not two eyes side by side", both.width, both.height));
  frame out;
  out.width = both.width / 2, out.height = both.height;
  const size_t w = size_t(out.width), skip = e == eye_side::left ? 0 : w;
  out.rgb.resize(w * out.height);
  out.depth.resize(out.rgb.size(), std::numeric_limits<float>::infinity());
  const bool depth = both.depth.size() == both.rgb.size();
  for (int y = 0; y < out.height; ++y) {
    const size_t from = size_t(y) * both.width + skip, to = size_t(y) * w;
    std::copy_n(both.rgb.begin() + from, w, out.rgb.begin() + to);
    if (depth) std::copy_n(both.depth.begin() + from, w, out.depth.begin() + to);
  }
  return out;
}

}  // namespace fov
