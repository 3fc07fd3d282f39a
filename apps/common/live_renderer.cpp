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
  pending_.reset();
  device_.reset();  // holds a reference to the old set
  set_ = std::move(set);
  device_ = std::make_unique<cl_reconstructor>(*set_);
  reset_history();
}

const std::string& live_renderer::device() const {
  static const std::string cpp = "C++ (TBB)";
  return device_ && device_->available() ? device_->device() : cpp;
}

trace_params live_renderer::params_for(const live_settings& s) {
  trace_params tp;
  tp.spp = s.spp;
  tp.shadows = s.shadows;
  tp.seed = 1 + (s.reseed && s.taa ? frame_ : 0);  // without TAA nothing integrates new positions
  ++frame_;
  return tp;
}

void live_renderer::begin_trace(double gx, double gy, const camera& view, const live_settings& s) {
  pending_.reset();  // waits for one still running
  const trace_params tp = params_for(s);
  auto job = [scn = scene_, set = set_, view, gx, gy, k = s.reconstruct.k, tp] {
    const auto t0 = std::chrono::steady_clock::now();
    traced out{trace_points(*scn, view, *set, gx, gy, k, tp), 0};
    out.ms = ms_since(t0);
    return out;
  };
  pending_ = pending_trace{gx, gy, view, s, set_, std::async(std::launch::async, std::move(job))};
}

const frame& live_renderer::foveated(double gx, double gy, const live_settings& s, live_timing* timing) {
  const auto t0 = std::chrono::steady_clock::now();
  point_samples samples;
  double trace_ms = 0, wait_ms = 0;
  bool ahead = false;
  if (pending_) {
    const pending_trace& p = *pending_;
    ahead = p.gaze_x == gx && p.gaze_y == gy && same_view(p.view, cam_) && p.set == set_ &&
            p.settings.spp == s.spp && p.settings.shadows == s.shadows && p.settings.reseed == s.reseed &&
            p.settings.taa == s.taa && p.settings.reconstruct.k == s.reconstruct.k;
    traced t = pending_->result.get();  // rethrows what the trace threw
    pending_.reset();
    if (ahead) samples = std::move(t.samples), trace_ms = t.ms, wait_ms = ms_since(t0);
  }
  if (!ahead) {
    samples = trace_points(*scene_, cam_, *set_, gx, gy, s.reconstruct.k, params_for(s));
    trace_ms = ms_since(t0);
  }
  const auto t1 = std::chrono::steady_clock::now();
  bool on_device = false;
  const double gaze[2] = {gx, gy};
  frame& f = frame_buffer_;
  double taa_ms = 0;
  if (s.taa) {  // reconstruction and TAA together: on the device the frame stays there
    device_->run_taa(samples, s.reconstruct, taa_, cam_, gaze, {}, f, &on_device);
    taa_ms = on_device ? device_->last_taa_kernel_ms() : 0;
  } else {
    device_->run(samples, s.reconstruct, f, &on_device);
    reset_history();
  }
  const auto t2 = std::chrono::steady_clock::now();
  if (timing) {
    // With TAA on the device, its share is the TAA kernel's time; on the C++ path it is
    // timed inside run_taa's fallback as part of the whole.
    timing->trace_ms = trace_ms;
    timing->traced_ahead = ahead;
    timing->trace_wait_ms = wait_ms;
    timing->reconstruct_ms = std::chrono::duration<double, std::milli>(t2 - t1).count() - taa_ms;
    timing->taa_ms = taa_ms;
    timing->rays = samples.rays;
    timing->points_traced = samples.traced.size();
    timing->on_device = on_device;
  }
  return f;
}

frame live_renderer::reference(int width, int height, uint32_t spp, bool shadows, live_timing* timing) {
  pending_.reset();
  trace_params tp;
  tp.spp = spp;
  tp.shadows = shadows;
  const auto t0 = std::chrono::steady_clock::now();
  frame f = trace_reference(*scene_, cam_, width, height, tp);
  if (timing) {
    *timing = live_timing{};
    timing->trace_ms = ms_since(t0);
    timing->rays = f.rays;
  }
  return f;
}

}  // namespace fov
