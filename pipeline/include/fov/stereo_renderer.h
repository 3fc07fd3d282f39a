// Two eyes through the one pipeline (fov/stereo.h): a renderer per eye (each its camera,
// reconstruction device and TAA history) over one scene and point set, the eyes' cameras
// placed from a head camera at every frame.
#pragma once

#include <memory>

#include "fov/renderer.h"
#include "fov/stereo.h"

namespace fov {

// What a stereo frame cost, per eye.
struct stereo_timing {
  frame_timing left, right;
};
// Both eyes' costs as one frame's: times, rays and points added up (cast by kind too); the
// right eye's reuse report (what --reuse eyes kept), the left eye's adaptive report, and
// on_device / traced_ahead when both eyes were.
frame_timing both_eyes(const stereo_timing& t);

class stereo_renderer {
 public:
  // The head camera is setup_camera(scene, p.view), each eye's eye_camera of it at p.stereo.ipd_mm.
  stereo_renderer(std::shared_ptr<const scene> s, const render_params& p);

  void use_pointset(std::shared_ptr<const pointset> set);  // both eyes'
  const camera& head() const { return head_; }
  void set_head(const camera& c);  // places both eyes (at the last frame's IPD)
  // One eye's renderer, its camera placed: for what a tool measures per eye (converged
  // references, warm-up). A frame rendered through it directly is that eye's alone.
  renderer& eye(eye_side e) { return e == eye_side::left ? left_ : right_; }

  // Both eyes' foveated frames at their gazes, side by side (left | right; valid until the
  // next call). With p.reuse.mode eyes the left eye is traced and the right one keeps the
  // left's samples where they hold (renderer::foveated_from), else each eye is its own
  // renderer's foveated() frame (temporal reuse, adaptive refinement and TAA per eye).
  const frame& foveated(gaze_point left, gaze_point right, const render_params& p, stereo_timing* t = nullptr);
  // Both eyes at full resolution (renderer::reference, width x height each), side by side.
  frame reference(int width, int height, const render_params& p, stereo_timing* t = nullptr);
  // The params one eye's renderer is given: p with its rolling scanout placed on that eye's
  // half of the panel (rolling_params::stereo). A tool that renders through eye(e) passes these.
  static render_params for_eye(const render_params& p, eye_side e);

 private:
  renderer left_, right_;
  camera head_;
  double ipd_mm_ = 0;
  frame frame_;
  void place_eyes(double ipd_mm);  // throws std::invalid_argument for an IPD out of range
};

}  // namespace fov
