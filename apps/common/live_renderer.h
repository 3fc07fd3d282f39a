// The per-frame pipeline the interactive tools share: trace the set's points at the gaze,
// reconstruct (OpenCL, C++ fallback), blend with TAA; or trace the full-resolution reference.
#pragma once

#include <memory>
#include <string>

#include "fov/camera.h"
#include "fov/cl_reconstruct.h"
#include "fov/pointset.h"
#include "fov/scene.h"
#include "fov/taa.h"
#include "fov/trace.h"

namespace fov {

struct live_settings {
  reconstruct_params reconstruct;
  uint32_t spp = 4;
  bool taa = true;
  bool reseed = true;  // new ray positions each frame (TAA integrates them)
  bool shadows = true;
};

struct live_timing {
  double trace_ms = 0, reconstruct_ms = 0, taa_ms = 0;
  uint64_t rays = 0, points_traced = 0;
  bool on_device = false;
};

class live_renderer {
 public:
  live_renderer(std::shared_ptr<const scene> scn, const camera& cam);
  // Uses `set` from now on (its first use builds the device state: seconds on a big set).
  void use_pointset(std::shared_ptr<const pointset> set);
  const pointset* current_set() const { return set_.get(); }
  camera& cam() { return cam_; }

  // One foveated frame at gaze (screen pixels). The TAA history carries over between
  // calls while the set and screen stay the same; reset_history() drops it.
  frame foveated(double gaze_x, double gaze_y, const live_settings& s, live_timing* timing = nullptr);
  // The full-resolution reference at `spp` rays per pixel (no TAA).
  frame reference(int width, int height, uint32_t spp, bool shadows, live_timing* timing = nullptr);
  void reset_history() { taa_ = taa_state{}; }
  const std::string& device() const;

 private:
  std::shared_ptr<const scene> scene_;
  camera cam_;
  std::shared_ptr<const pointset> set_;
  std::unique_ptr<cl_reconstructor> device_;
  taa_state taa_;
  uint64_t frame_ = 0;
};

}  // namespace fov
