// Reconstruction on an OpenCL device (PoCL on the CPU here), with the C++ path behind it.
#pragma once

#include <memory>
#include <string>

#include "fov/reconstruct.h"
#include "fov/taa.h"

struct _cl_event;  // OpenCL handles, declared so this header needs no CL headers
struct _cl_mem;

namespace fov {

class rbf_weight_cache;

class cl_reconstructor {
 public:
  // Builds the kernels and uploads the set's points and table once. Never throws for a
  // missing or failing OpenCL platform: available() is then false and reason() says why.
  // The table is copied to the device once (on PoCL that is a second copy in host
  // memory); the set must outlive the reconstructor, which falls back to it.
  explicit cl_reconstructor(const pointset& set);
  ~cl_reconstructor();
  cl_reconstructor(const cl_reconstructor&) = delete;
  cl_reconstructor& operator=(const cl_reconstructor&) = delete;

  bool available() const;
  const std::string& device() const;  // platform and device names
  const std::string& reason() const;  // why unavailable

  // Every method runs on the device, or on the C++ path when the device is unavailable;
  // `on_device` tells which ran. RBF reads geometry-only weights (rbf_cache.h) that the
  // first RBF run for the screen's tiles computes on the host and copies to the device;
  // later runs with the same k, kernel and shape only form weighted sums.
  frame run(const point_samples& samples, const reconstruct_params& params, bool* on_device = nullptr,
            rbf_stats* stats = nullptr);
  // The same into `out`, reusing its storage when it has the screen's size (a live loop
  // saves zero-filling 29 MB a FOVE frame).
  void run(const point_samples& samples, const reconstruct_params& params, frame& out, bool* on_device = nullptr,
           rbf_stats* stats = nullptr);

  // run() followed by taa_resolve(), with the frame kept on the device in between and the
  // history kept there across calls (uploaded only when `state` was last advanced
  // elsewhere). Same results as the C++ pair within float rounding; falls back to it.
  frame run_taa(const point_samples& samples, const reconstruct_params& params, taa_state& state, const camera& cam,
                const double gaze[2], const taa_params& taa = {}, bool* on_device = nullptr, rbf_stats* stats = nullptr);
  void run_taa(const point_samples& samples, const reconstruct_params& params, taa_state& state, const camera& cam,
               const double gaze[2], const taa_params& taa, frame& out, bool* on_device = nullptr,
               rbf_stats* stats = nullptr);

  // The RBF weights kept so far (null before the first RBF run): its seconds() is the
  // one-time cost, its stats() the solves' fallbacks and condition numbers.
  const rbf_weight_cache* rbf_cache() const;

  // Device time of the last kernel run() launched (profiling events; transfers excluded).
  double last_kernel_ms() const;
  // Device time of the last TAA kernel run_taa() launched (0 when it had no history).
  double last_taa_kernel_ms() const;
  // Bandwidth of a plain copy kernel over `bytes` (read + write counted), best of `repeats`.
  double copy_gigabytes_per_second(size_t bytes, int repeats = 5);

 private:
  struct impl;
  std::unique_ptr<impl> impl_;
  rbf_weight_cache* prepare_rbf(const reconstruct_params& params);  // null unless RBF
  ::_cl_event* launch(const point_samples& samples, const reconstruct_params& params, rbf_stats* stats);
  void read_back(::_cl_mem* rgb, frame& out);
  const pointset& set_;
};

}  // namespace fov
