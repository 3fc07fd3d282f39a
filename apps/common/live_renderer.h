// The per-frame pipeline the interactive tools share: trace the set's points at the gaze,
// reconstruct (OpenCL, C++ fallback), blend with TAA; or trace the full-resolution reference.
#pragma once

#include <future>
#include <memory>
#include <optional>
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
  bool reseed = true;  // new ray positions each frame while TAA is on (it integrates them)
  bool shadows = true;
};

struct live_timing {
  double trace_ms = 0, reconstruct_ms = 0, taa_ms = 0;
  // With begin_trace: the trace ran in the background while the caller showed the frame
  // before; trace_wait_ms is how long foveated() still waited for it.
  bool traced_ahead = false;
  double trace_wait_ms = 0;
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

  // One foveated frame at gaze (screen pixels), valid until the next call (its storage is
  // reused frame to frame). The TAA history carries over between calls while the set and
  // screen stay the same; reset_history() drops it.
  const frame& foveated(double gaze_x, double gaze_y, const live_settings& s, live_timing* timing = nullptr);
  // Pipelining: starts tracing the frame for this gaze, camera and settings in the
  // background, so it overlaps whatever the caller does next (showing the frame before).
  // The next foveated() call with the same gaze, camera (cam() set to `view`), settings
  // and set takes those samples; any other call drops them and traces anew.
  void begin_trace(double gaze_x, double gaze_y, const camera& view, const live_settings& s);
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
  frame frame_buffer_;  // what foveated() returns

  trace_params params_for(const live_settings& s);  // the next frame's ray pattern
  struct traced {
    point_samples samples;
    double ms = 0;
  };
  struct pending_trace {
    double gaze_x, gaze_y;
    camera view;
    live_settings settings;
    std::shared_ptr<const pointset> set;
    std::future<traced> result;
  };
  std::optional<pending_trace> pending_;  // last: waited for before the rest goes
};

}  // namespace fov
