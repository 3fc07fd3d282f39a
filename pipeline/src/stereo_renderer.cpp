#include "fov/stereo_renderer.h"

#include <stdexcept>

namespace fov {

stereo_renderer::stereo_renderer(std::shared_ptr<const scene> s, const render_params& p)
    : left_(s, p), right_(s, p), head_(left_.cam()) {
  place_eyes(p.stereo.ipd_mm);
}

void stereo_renderer::use_pointset(std::shared_ptr<const pointset> set) {
  left_.use_pointset(set);
  right_.use_pointset(std::move(set));
}

void stereo_renderer::set_head(const camera& c) {
  head_ = c;
  place_eyes(ipd_mm_);
}

void stereo_renderer::place_eyes(double ipd_mm) {
  stereo_params checked;
  checked.ipd_mm = ipd_mm;
  if (const std::string why = validate(checked); !why.empty()) throw std::invalid_argument(why);
  ipd_mm_ = ipd_mm;
  left_.cam() = eye_camera(head_, eye_side::left, ipd_mm);
  right_.cam() = eye_camera(head_, eye_side::right, ipd_mm);
}

render_params stereo_renderer::for_eye(const render_params& p, eye_side e) {
  render_params q = p;
  q.rolling.stereo = true, q.rolling.right_eye = e == eye_side::right, q.rolling.ipd_mm = p.stereo.ipd_mm;
  return q;
}

const frame& stereo_renderer::foveated(gaze_point left, gaze_point right, const render_params& p, stereo_timing* t) {
  place_eyes(p.stereo.ipd_mm);
  stereo_timing st;
  const render_params pl = for_eye(p, eye_side::left), pr = for_eye(p, eye_side::right);
  const frame& l = left_.foveated(left, pl, &st.left);
  if (p.reuse.mode == reuse_mode::eyes) {
    const reuse_history other = history_of(left_.last_samples(), left_.cam(), *left_.current_set(), p.spp);
    frame_ = side_by_side(l, right_.foveated_from(other, right, pr, &st.right));
  } else {
    frame_ = side_by_side(l, right_.foveated(right, pr, &st.right));
  }
  if (t) *t = st;
  return frame_;
}

frame stereo_renderer::reference(int width, int height, const render_params& p, stereo_timing* t) {
  place_eyes(p.stereo.ipd_mm);
  stereo_timing st;
  const reference_trace l = left_.reference(width, height, for_eye(p, eye_side::left), &st.left);
  const reference_trace r = right_.reference(width, height, for_eye(p, eye_side::right), &st.right);
  if (t) *t = st;
  return side_by_side(l.image, r.image);
}

frame_timing both_eyes(const stereo_timing& t) {
  frame_timing b = t.left;
  const frame_timing& r = t.right;
  b.trace_ms += r.trace_ms, b.reconstruct_ms += r.reconstruct_ms, b.taa_ms += r.taa_ms, b.trace_wait_ms += r.trace_wait_ms;
  b.traced_ahead = b.traced_ahead && r.traced_ahead;
  b.rays += r.rays, b.points_traced += r.points_traced;
  b.cast.primary += r.cast.primary, b.cast.shadow += r.cast.shadow, b.cast.bounce += r.cast.bounce;
  b.on_device = b.on_device && r.on_device;
  b.weights += r.weights;
  b.reused = r.reused, b.reuse = r.reuse;
  return b;
}

}  // namespace fov
