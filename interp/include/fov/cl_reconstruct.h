// Reconstruction on an OpenCL device (PoCL on the CPU here), with the C++ path behind it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fov/labels.h"
#include "fov/reconstruct.h"
#include "fov/taa.h"

struct _cl_event;  // OpenCL handles, declared so this header needs no CL headers
struct _cl_mem;

namespace fov {

class weight_cache;

// Where reconstruction runs: the OpenCL kernels (falling back to C++ when no device can
// be had) or the C++ path alone.
enum class reconstruct_device : uint8_t { opencl, cpp };
inline constexpr std::pair<const char*, reconstruct_device> reconstruct_device_labels[] = {
    {"opencl", reconstruct_device::opencl}, {"cpp", reconstruct_device::cpp}};

// What one run did.
struct reconstruct_result {
  bool on_device = false;    // the kernels ran (else the C++ path)
  weight_stats weights;             // RBF only: the weight solves' fallbacks and conditioning
  double kernel_ms = 0;      // device time of the reconstruction kernel (profiling events)
  double taa_kernel_ms = 0;  // run_taa on the device: the TAA kernel's time (0 without history)
  // On the device, host wall times: the samples' upload (colours converted into a mapped
  // buffer, depths enqueued) and the frame's read-back (depth download, image map, conversion
  // to the frame's layout), which starts once the kernels are done.
  double upload_ms = 0;
  double read_back_ms = 0;
};

class cl_reconstructor {
 public:
  // Builds the kernels and uploads the set's points and table once. Never throws for a
  // missing or failing OpenCL platform: available() is then false and reason() says why.
  // With reconstruct_device::cpp no platform is touched and every run takes the C++ path.
  // The table is copied to the device once (on PoCL that is a second copy in host
  // memory); the set must outlive the reconstructor, which falls back to it.
  // `weight_caches` is how many cached-weight configurations (method, k, kernel, shape:
  // weight_cache.h) are kept at once, the one used longest ago replaced by a new one; each
  // holds k floats per canvas pixel a screen has covered, on the host and on the device.
  explicit cl_reconstructor(const pointset& set, reconstruct_device where = reconstruct_device::opencl,
                            uint32_t weight_caches = default_weight_caches);
  static constexpr uint32_t default_weight_caches = 2, max_weight_caches = 16;
  ~cl_reconstructor();
  cl_reconstructor(const cl_reconstructor&) = delete;
  cl_reconstructor& operator=(const cl_reconstructor&) = delete;

  bool available() const;
  const std::string& device() const;  // platform and device names, or "C++ (TBB)"
  const std::string& reason() const;  // why unavailable

  // Every method runs on the device, or on the C++ path when the device is unavailable.
  // RBF reads geometry-only weights (weight_cache.h) that the first RBF run for the screen's
  // tiles computes on the host and copies to the device; later runs with the same k,
  // kernel and shape only form weighted sums. `out` keeps its storage when it has the
  // screen's size (a live loop saves zero-filling 29 MB a FOVE frame).
  // With `only` (an adaptive frame's level), only that level's pixels are rebuilt; `out`'s other
  // pixels are then unspecified.
  reconstruct_result run(const point_samples& samples, const reconstruct_params& params, frame& out,
                         const level_mask* only = nullptr);
  frame run(const point_samples& samples, const reconstruct_params& params);

  // run() followed by taa_resolve(), with the frame kept on the device in between and the
  // history kept there across calls (uploaded only when `state` was last advanced
  // elsewhere). Same results as the C++ pair within float rounding; falls back to it.
  reconstruct_result run_taa(const point_samples& samples, const reconstruct_params& params, taa_state& state,
                             const camera& cam, gaze_point gaze, const taa_params& taa, frame& out);
  frame run_taa(const point_samples& samples, const reconstruct_params& params, taa_state& state, const camera& cam,
                gaze_point gaze, const taa_params& taa = {});

  // The RBF weights kept so far (null before the first RBF run): its seconds() is the
  // one-time cost, its stats() the solves' fallbacks and condition numbers.
  const weight_cache* cached_weights() const;
  size_t weight_caches_held() const;  // configurations whose weights are kept now

  // Bandwidth of a plain copy kernel over `bytes` (read + write counted), best of `repeats`.
  double copy_gigabytes_per_second(size_t bytes, int repeats = 5);

  // The options the kernels are built with: every constant they share with C++ (-D).
  static std::string kernel_build_options();
  // The layout of the TAA camera struct, as the host sees it and as the device's compiler
  // lays it out: sizeof, then the offset of each field. They must be equal (a test checks).
  static std::vector<uint32_t> host_taa_camera_layout();
  std::vector<uint32_t> device_taa_camera_layout();  // empty when no device

 private:
  struct impl;
  std::unique_ptr<impl> impl_;
  weight_cache* prepare_weights(const reconstruct_params& params);  // null unless RBF
  ::_cl_event* launch(const point_samples& samples, const reconstruct_params& params, reconstruct_result& result,
                      const level_mask* only = nullptr);
  double read_back(::_cl_mem* rgb, frame& out);  // milliseconds it took
  const pointset& set_;
};

}  // namespace fov
