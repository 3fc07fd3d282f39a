#include "live_renderer.h"

#include <chrono>

namespace fov {

namespace {
double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

live_renderer::live_renderer(std::shared_ptr<const scene> scn, const camera& cam) : scene_(std::move(scn)), cam_(cam) {}

void live_renderer::use_pointset(std::shared_ptr<const pointset> set) {
  if (set == set_) return;
  device_.reset();  // holds a reference to the old set
  set_ = std::move(set);
  device_ = std::make_unique<cl_reconstructor>(*set_);
  reset_history();
}

const std::string& live_renderer::device() const {
  static const std::string cpp = "C++ (TBB)";
  return device_ && device_->available() ? device_->device() : cpp;
}

frame live_renderer::foveated(double gx, double gy, const live_settings& s, live_timing* timing) {
  trace_params tp;
  tp.spp = s.spp;
  tp.shadows = s.shadows;
  tp.seed = 1 + (s.reseed ? frame_ : 0);
  ++frame_;
  const auto t0 = std::chrono::steady_clock::now();
  const point_samples samples = trace_points(*scene_, cam_, *set_, gx, gy, s.reconstruct.k, tp);
  const auto t1 = std::chrono::steady_clock::now();
  bool on_device = false;
  const double gaze[2] = {gx, gy};
  frame f;
  double taa_ms = 0;
  if (s.taa) {  // reconstruction and TAA together: on the device the frame stays there
    f = device_->run_taa(samples, s.reconstruct, taa_, cam_, gaze, {}, &on_device);
    taa_ms = on_device ? device_->last_taa_kernel_ms() : 0;
  } else {
    f = device_->run(samples, s.reconstruct, &on_device);
    reset_history();
  }
  const auto t2 = std::chrono::steady_clock::now();
  if (timing) {
    // With TAA on the device, its share is the TAA kernel's time; on the C++ path it is
    // timed inside run_taa's fallback as part of the whole.
    timing->trace_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    timing->reconstruct_ms = std::chrono::duration<double, std::milli>(t2 - t1).count() - taa_ms;
    timing->taa_ms = taa_ms;
    timing->rays = samples.rays;
    timing->points_traced = samples.traced.size();
    timing->on_device = on_device;
  }
  return f;
}

frame live_renderer::reference(int width, int height, uint32_t spp, bool shadows, live_timing* timing) {
  trace_params tp;
  tp.spp = spp;
  tp.shadows = shadows;
  const auto t0 = std::chrono::steady_clock::now();
  frame f = trace_reference(*scene_, cam_, width, height, tp);
  if (timing) *timing = live_timing{ms_since(t0), 0, 0, f.rays, 0, false};
  return f;
}

}  // namespace fov
