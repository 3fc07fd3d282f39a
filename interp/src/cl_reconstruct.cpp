#define CL_TARGET_OPENCL_VERSION 120
#include "fov/cl_reconstruct.h"

#include <CL/cl.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "fov/kernel_sources.h"
#include "fov/weight_cache.h"

namespace fov {

namespace {

struct cl_failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void check(cl_int status, const char* what) {
  if (status != CL_SUCCESS) throw cl_failure(fmt::format("{} failed (OpenCL error {})", what, status));
}

// A string property of a platform or device: query(size, buffer, &needed).
template <class Query>
std::string info_text(Query&& query) {
  size_t n = 0;
  query(0, nullptr, &n);
  std::string s(n, '\0');
  query(n, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

// Milliseconds between a finished event's start and end.
double event_ms(cl_event e) {
  cl_ulong start = 0, end = 0;
  clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_START, sizeof(start), &start, nullptr);
  clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_END, sizeof(end), &end, nullptr);
  return double(end - start) * 1e-6;
}

}  // namespace

struct cl_reconstructor::impl {
  bool ok = false;
  std::string device, reason;
  cl_context context = nullptr;
  cl_command_queue queue = nullptr;
  cl_program program = nullptr;
  cl_kernel nn = nullptr, shepard = nullptr, weighted = nullptr, copy = nullptr, taa = nullptr, layout = nullptr;
  cl_mem history = nullptr, taa_out = nullptr;  // TAA: the previous output and the next one
  uint64_t history_generation = 0;              // taa_state::generation that `history` holds
  // The table, or the cells packed: tiles, then cell offsets from cell_start_at, then
  // candidates from candidates_at (kernels/reconstruct.cl, neighbours()).
  cl_ulong cell_start_at = 0, candidates_at = 0;
  cl_mem table = nullptr, position = nullptr, colour = nullptr, depth = nullptr, out_rgb = nullptr, out_depth = nullptr;
  cl_mem level_map = nullptr;  // an adaptive frame's refinement map (launch's level_mask)
  size_t level_map_bytes = 0;
  // Cached weights, one slot per (method, k, kernel, shape) in use: the `slots_kept` used last are
  // kept, so a sweep that alternates them does not compute its weights again at every switch.
  struct weight_slot {
    std::unique_ptr<weight_cache> cache;
    cl_mem weights = nullptr;  // the cache's tiles on the device
    uint64_t used = 0;
  };
  size_t slots_kept = cl_reconstructor::default_weight_caches;
  std::vector<weight_slot> caches;
  uint64_t weights_clock = 0;
  weight_slot* last_weights = nullptr;

  ~impl() {
    for (cl_mem m : {table, position, colour, depth, out_rgb, out_depth, history, taa_out, level_map})
      if (m) clReleaseMemObject(m);
    for (weight_slot& r : caches)
      if (r.weights) clReleaseMemObject(r.weights);
    for (cl_kernel k : {nn, shepard, weighted, copy, taa, layout})
      if (k) clReleaseKernel(k);
    if (program) clReleaseProgram(program);
    if (queue) clReleaseCommandQueue(queue);
    if (context) clReleaseContext(context);
  }

  void setup(const pointset& set) {
    cl_uint platforms = 0;
    if (clGetPlatformIDs(0, nullptr, &platforms) != CL_SUCCESS || platforms == 0) throw cl_failure("no OpenCL platform");
    std::vector<cl_platform_id> ids(platforms);
    check(clGetPlatformIDs(platforms, ids.data(), nullptr), "clGetPlatformIDs");
    cl_device_id dev = nullptr;
    for (cl_platform_id p : ids) {
      cl_uint n = 0;
      if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 1, &dev, &n) == CL_SUCCESS && n > 0) {
        device = info_text([&](size_t n, void* b, size_t* need) { return clGetPlatformInfo(p, CL_PLATFORM_NAME, n, b, need); }) +
                 " / " + info_text([&](size_t n, void* b, size_t* need) { return clGetDeviceInfo(dev, CL_DEVICE_NAME, n, b, need); });
        break;
      }
      dev = nullptr;
    }
    if (!dev) throw cl_failure("no OpenCL device");
    cl_int status = 0;
    context = clCreateContext(nullptr, 1, &dev, nullptr, nullptr, &status);
    check(status, "clCreateContext");
    queue = clCreateCommandQueue(context, dev, CL_QUEUE_PROFILING_ENABLE, &status);
    check(status, "clCreateCommandQueue");
    const char* sources[2] = {kernel_sources::reconstruct, kernel_sources::taa};
    program = clCreateProgramWithSource(context, 2, sources, nullptr, &status);
    check(status, "clCreateProgramWithSource");
    const std::string options = kernel_build_options();
    if (clBuildProgram(program, 1, &dev, options.c_str(), nullptr, nullptr) != CL_SUCCESS) {
      size_t n = 0;
      clGetProgramBuildInfo(program, dev, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
      std::string log(n, '\0');
      clGetProgramBuildInfo(program, dev, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
      throw cl_failure("kernel build failed: " + log.substr(0, 300));
    }
    nn = clCreateKernel(program, "reconstruct_nn", &status);
    check(status, "clCreateKernel(reconstruct_nn)");
    shepard = clCreateKernel(program, "reconstruct_shepard", &status);
    check(status, "clCreateKernel(reconstruct_shepard)");
    weighted = clCreateKernel(program, "reconstruct_weighted", &status);
    check(status, "clCreateKernel(reconstruct_weighted)");
    taa = clCreateKernel(program, "taa_resolve", &status);
    check(status, "clCreateKernel(taa_resolve)");
    copy = clCreateKernel(program, "copy_float4", &status);
    check(status, "clCreateKernel(copy_float4)");
    layout = clCreateKernel(program, "taa_camera_layout", &status);
    check(status, "clCreateKernel(taa_camera_layout)");

    const knn_table& t = set.table;
    if (t.k != 0) {
      table = clCreateBuffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, t.entries.size() * sizeof(uint32_t),
                             const_cast<uint32_t*>(t.entries.data()), &status);
    } else {  // the cells, packed as the kernels read them: tiles, cell offsets, candidates
      const knn_cells& c = set.cells;
      cell_start_at = c.tiles.size();
      candidates_at = cell_start_at + c.cell_start.size();
      table = clCreateBuffer(context, CL_MEM_READ_ONLY, (candidates_at + c.candidates.size()) * sizeof(uint32_t), nullptr,
                             &status);
      check(status, "cells buffer");
      for (const auto& [at, part] : {std::pair{size_t(0), &c.tiles}, {cell_start_at, &c.cell_start}, {candidates_at, &c.candidates}})
        check(clEnqueueWriteBuffer(queue, table, CL_TRUE, at * sizeof(uint32_t), part->size() * sizeof(uint32_t),
                                   part->data(), 0, nullptr, nullptr), "cells upload");
    }
    check(status, "table buffer");
    std::vector<cl_float2> xy(set.points.size());
    for (size_t i = 0; i < xy.size(); ++i) xy[i] = {{set.points[i].x, set.points[i].y}};
    position = clCreateBuffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, xy.size() * sizeof(cl_float2),
                              xy.data(), &status);
    check(status, "position buffer");
    colour = clCreateBuffer(context, CL_MEM_READ_ONLY, set.points.size() * sizeof(cl_float4), nullptr, &status);
    check(status, "colour buffer");
    depth = clCreateBuffer(context, CL_MEM_READ_ONLY, set.points.size() * sizeof(float), nullptr, &status);
    check(status, "depth buffer");
    const size_t pixels = size_t(set.model.display.width) * set.model.display.height;
    out_rgb = clCreateBuffer(context, CL_MEM_READ_WRITE, pixels * sizeof(cl_float4), nullptr, &status);
    check(status, "image buffer");
    out_depth = clCreateBuffer(context, CL_MEM_READ_WRITE, pixels * sizeof(float), nullptr, &status);
    check(status, "depth image buffer");
    history = clCreateBuffer(context, CL_MEM_READ_WRITE, pixels * sizeof(cl_float4), nullptr, &status);
    check(status, "TAA history buffer");
    taa_out = clCreateBuffer(context, CL_MEM_READ_WRITE, pixels * sizeof(cl_float4), nullptr, &status);
    check(status, "TAA output buffer");
    ok = true;
  }
};

cl_reconstructor::cl_reconstructor(const pointset& set, reconstruct_device where, uint32_t weight_caches)
    : impl_(std::make_unique<impl>()), set_(set) {
  require_neighbours(set);
  if (weight_caches < 1 || weight_caches > max_weight_caches)
    throw std::invalid_argument(fmt::format("cl_reconstructor: weight_caches must lie in 1..{} (got {})", max_weight_caches, weight_caches));
  impl_->slots_kept = weight_caches;
  if (where == reconstruct_device::cpp) {
    impl_->reason = "the C++ path was asked for";
    return;
  }
  try {
    impl_->setup(set);
  } catch (const cl_failure& e) {
    impl_->ok = false;
    impl_->reason = e.what();
  }
}

cl_reconstructor::~cl_reconstructor() = default;
bool cl_reconstructor::available() const { return impl_->ok; }
const std::string& cl_reconstructor::device() const {
  static const std::string cpp = "C++ (TBB)";
  return impl_->ok ? impl_->device : cpp;
}
const std::string& cl_reconstructor::reason() const { return impl_->reason; }

std::string cl_reconstructor::kernel_build_options() {
  return fmt::format(
      "-cl-std=CL1.2 -DFOV_MAX_K={} -DFOV_WEIGHT_TILE={} -DFOV_CELL_TILE={} -DFOV_ON_POINT={:.9g}f -DFOV_BLOCK={} "
      "-DFOV_SHEPARD_TIE={:.9g}f",
      max_knn, weight_cache::tile, knn_cells::tile, on_point_px, refinement_block, shepard_tie);
}

frame cl_reconstructor::run(const point_samples& samples, const reconstruct_params& params) {
  frame out;
  run(samples, params, out);
  return out;
}

reconstruct_result cl_reconstructor::run(const point_samples& samples, const reconstruct_params& params, frame& out,
                                         const level_mask* only) {
  impl& d = *impl_;
  check_reconstruct_inputs(set_, samples, params);
  reconstruct_result result;
  result.on_device = d.ok;
  if (!d.ok) {
    reconstruct_into(set_, samples, params, out, &result.weights, prepare_weights(params), only);
    return result;
  }
  cl_event done = launch(samples, params, result, only);
  check(clWaitForEvents(1, &done), "kernel wait");
  result.read_back_ms = read_back(impl_->out_rgb, out);
  result.kernel_ms = event_ms(done);
  clReleaseEvent(done);
  return result;
}

weight_cache* cl_reconstructor::prepare_weights(const reconstruct_params& params) {
  impl& d = *impl_;
  if (!cached_weights_method(params.how)) return nullptr;
  auto slot = std::find_if(d.caches.begin(), d.caches.end(), [&](const impl::weight_slot& r) { return r.cache->serves(params); });
  if (slot == d.caches.end()) {
    if (d.caches.size() < d.slots_kept) {
      slot = d.caches.insert(d.caches.end(), impl::weight_slot{});
    } else {  // replace the one used longest ago
      slot = std::min_element(d.caches.begin(), d.caches.end(), [](const auto& a, const auto& b) { return a.used < b.used; });
      if (slot->weights) clReleaseMemObject(slot->weights), slot->weights = nullptr;
    }
    slot->cache = std::make_unique<weight_cache>(set_, params);
  }
  slot->used = ++d.weights_clock;
  d.last_weights = &*slot;
  return slot->cache.get();
}

cl_event cl_reconstructor::launch(const point_samples& samples, const reconstruct_params& params,
                                  reconstruct_result& result, const level_mask* only) {
  impl& d = *impl_;
  const knn_table& t = set_.table;
  weight_cache* cache = prepare_weights(params);
  const bool rbf = cache != nullptr;
  cl_mem weights = nullptr;
  if (rbf) {  // compute the weights the screen needs and copy the new tiles to the device
    cl_mem& slot_weights = d.last_weights->weights;
    cl_int status = 0;
    if (!slot_weights) {
      slot_weights = clCreateBuffer(d.context, CL_MEM_READ_ONLY, cache->floats() * sizeof(float), nullptr, &status);
      check(status, "RBF weight buffer");  // made with its cache: no tile is computed yet
    }
    weights = slot_weights;
    const size_t tile_bytes = cache->tile_floats() * sizeof(float);
    for (uint32_t index : cache->prepare(samples.offset))
      check(clEnqueueWriteBuffer(d.queue, weights, CL_FALSE, index * tile_bytes, tile_bytes,
                                 cache->data() + size_t(index) * cache->tile_floats(), 0, nullptr, nullptr),
            "RBF weight upload");
    result.weights = cache->stats();
  }

  // Colours are written straight into the mapped device buffer (on a CPU device a
  // mapping is the buffer itself: no staging copy).
  const auto upload_start = std::chrono::steady_clock::now();
  cl_int status = 0;
  auto* colours = static_cast<cl_float4*>(clEnqueueMapBuffer(d.queue, d.colour, CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0,
                                                             samples.colour.size() * sizeof(cl_float4), 0, nullptr,
                                                             nullptr, &status));
  check(status, "colour map");
  tbb::parallel_for(tbb::blocked_range<size_t>(0, samples.colour.size(), 1 << 15), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i)
      colours[i] = {{samples.colour[i].r, samples.colour[i].g, samples.colour[i].b, 1.0f}};
  });
  check(clEnqueueUnmapMemObject(d.queue, d.colour, colours, 0, nullptr, nullptr), "colour unmap");
  check(clEnqueueWriteBuffer(d.queue, d.depth, CL_FALSE, 0, samples.depth.size() * sizeof(float), samples.depth.data(),
                             0, nullptr, nullptr), "depth upload");
  result.upload_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - upload_start).count();

  const cl_uint cells = t.k == 0 ? 1 : 0, cell_tiles_x = set_.cells.tiles_x();
  const cl_uint canvas_width = set_.canvas_width(), k_stored = stored_k(set_), group = t.group;
  const cl_uint width = cl_uint(set_.model.display.width);
  const cl_ulong pixel_count = t.pixel_count();
  const cl_int ox = samples.offset.x, oy = samples.offset.y;
  const cl_uint k = params.k, renka = params.renka ? 1 : 0;
  cl_kernel kernel = params.how == method::nn ? d.nn : params.how == method::shepard ? d.shepard : d.weighted;
  const cl_uint tiles_x = rbf ? cache->tiles_x() : 0;
  cl_uint a = 0;
  auto arg = [&](const auto& value) { check(clSetKernelArg(kernel, a++, sizeof(value), &value), "clSetKernelArg"); };
  const cl_uint mirror_x = samples.mirror_x ? 1 : 0, mirror_y = samples.mirror_y ? 1 : 0;
  arg(d.table), arg(cells), arg(canvas_width), arg(k_stored), arg(group), arg(pixel_count), arg(cell_tiles_x);
  arg(d.cell_start_at), arg(d.candidates_at), arg(d.position), arg(ox), arg(oy), arg(width), arg(mirror_x), arg(mirror_y);
  // The refinement map, when only one level's pixels are wanted (a byte per block; a dummy byte otherwise).
  const size_t map_bytes = only ? only->map->level.size() : 1;
  if (map_bytes > d.level_map_bytes) {
    if (d.level_map) clReleaseMemObject(d.level_map), d.level_map = nullptr;
    d.level_map = clCreateBuffer(d.context, CL_MEM_READ_ONLY, map_bytes, nullptr, &status);
    check(status, "level map buffer");
    d.level_map_bytes = map_bytes;
  }
  if (only)
    check(clEnqueueWriteBuffer(d.queue, d.level_map, CL_FALSE, 0, map_bytes, only->map->level.data(), 0, nullptr, nullptr),
          "level map upload");
  const cl_uint map_on = only ? 1 : 0, map_level = only ? only->level : 0, map_x0 = only ? only->map->x0 : 0,
                map_y0 = only ? only->map->y0 : 0, map_blocks_x = only ? only->map->blocks_x : 0;
  arg(d.level_map), arg(map_on), arg(map_level), arg(map_x0), arg(map_y0), arg(map_blocks_x);
  if (params.how == method::shepard) arg(k), arg(renka);
  if (rbf) arg(k), arg(renka), arg(weights), arg(tiles_x);
  arg(d.colour), arg(d.depth), arg(d.out_rgb), arg(d.out_depth);
  const size_t global[2] = {size_t(set_.model.display.width), size_t(set_.model.display.height)};
  cl_event done = nullptr;
  check(clEnqueueNDRangeKernel(d.queue, kernel, 2, nullptr, global, nullptr, 0, nullptr, &done), "kernel launch");
  return done;
}

double cl_reconstructor::read_back(cl_mem rgb, frame& out) {
  const auto start = std::chrono::steady_clock::now();
  impl& d = *impl_;
  out.width = set_.model.display.width;
  out.height = set_.model.display.height;
  out.rays = 0;
  const size_t pixels = size_t(out.width) * out.height;
  out.depth.resize(pixels);  // no-ops when `out` is reused
  check(clEnqueueReadBuffer(d.queue, d.out_depth, CL_FALSE, 0, pixels * sizeof(float), out.depth.data(), 0, nullptr,
                            nullptr), "depth download");
  // The image is read through a mapping (no staging copy on a CPU device).
  cl_int status = 0;
  const auto* image = static_cast<const cl_float4*>(clEnqueueMapBuffer(d.queue, rgb, CL_TRUE, CL_MAP_READ, 0,
                                                                       pixels * sizeof(cl_float4), 0, nullptr, nullptr,
                                                                       &status));
  check(status, "image map");
  out.rgb.resize(pixels);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 15), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) out.rgb[i] = {image[i].s[0], image[i].s[1], image[i].s[2]};
  });
  check(clEnqueueUnmapMemObject(d.queue, rgb, const_cast<cl_float4*>(image), 0, nullptr, nullptr), "image unmap");
  check(clFinish(d.queue), "read-back");
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

namespace {

struct alignas(16) cl_taa_camera {  // kernels/taa.cl: taa_camera (host_taa_camera_layout)
  cl_float4 origin, right, up, forward;
  cl_float half_width, half_height;
};

cl_taa_camera to_cl(const camera_frame& f) {
  auto v = [](const glm::vec3& x) { return cl_float4{{x.x, x.y, x.z, 0}}; };
  return {v(f.origin), v(f.right), v(f.up), v(f.forward), f.half_width, f.half_height};
}

}  // namespace

std::vector<uint32_t> cl_reconstructor::host_taa_camera_layout() {
  return {uint32_t(sizeof(cl_taa_camera)),
          uint32_t(offsetof(cl_taa_camera, origin)),
          uint32_t(offsetof(cl_taa_camera, right)),
          uint32_t(offsetof(cl_taa_camera, up)),
          uint32_t(offsetof(cl_taa_camera, forward)),
          uint32_t(offsetof(cl_taa_camera, half_width)),
          uint32_t(offsetof(cl_taa_camera, half_height))};
}

std::vector<uint32_t> cl_reconstructor::device_taa_camera_layout() {
  impl& d = *impl_;
  if (!d.ok) return {};
  std::vector<uint32_t> out(7, 0);
  cl_int status = 0;
  cl_mem buffer = clCreateBuffer(d.context, CL_MEM_WRITE_ONLY, out.size() * sizeof(uint32_t), nullptr, &status);
  check(status, "layout buffer");
  check(clSetKernelArg(d.layout, 0, sizeof(cl_mem), &buffer), "clSetKernelArg");
  const size_t one = 1;
  check(clEnqueueNDRangeKernel(d.queue, d.layout, 1, nullptr, &one, nullptr, 0, nullptr, nullptr), "layout launch");
  check(clEnqueueReadBuffer(d.queue, buffer, CL_TRUE, 0, out.size() * sizeof(uint32_t), out.data(), 0, nullptr, nullptr),
        "layout read");
  clReleaseMemObject(buffer);
  return out;
}

frame cl_reconstructor::run_taa(const point_samples& samples, const reconstruct_params& params, taa_state& state,
                                const camera& cam, gaze_point gaze, const taa_params& taa) {
  frame out;
  run_taa(samples, params, state, cam, gaze, taa, out);
  return out;
}

reconstruct_result cl_reconstructor::run_taa(const point_samples& samples, const reconstruct_params& params,
                                             taa_state& state, const camera& cam, gaze_point gaze,
                                             const taa_params& taa, frame& out) {
  impl& d = *impl_;
  check_reconstruct_inputs(set_, samples, params);
  if (!(taa.alpha > 0 && taa.alpha <= 1)) throw std::invalid_argument("TAA alpha must lie in (0, 1]");
  const display_geometry& display = set_.model.display;
  reconstruct_result result;
  result.on_device = d.ok;
  if (!d.ok) {
    const frame current = reconstruct(set_, samples, params, &result.weights, prepare_weights(params));
    out = taa_resolve(state, current, cam, display, gaze, taa);
    return result;
  }
  const int w = display.width, h = display.height;
  const size_t pixels = size_t(w) * h;
  cl_event done = launch(samples, params, result);
  const bool usable = state.valid && state.history.width == w && state.history.height == h;
  double taa_ms = 0;
  if (usable) {
    if (d.history_generation != state.generation || !d.history) {  // the history is not on the device yet
      std::vector<cl_float4> host(pixels);
      for (size_t i = 0; i < pixels; ++i) host[i] = {{state.history.rgb[i].r, state.history.rgb[i].g, state.history.rgb[i].b, 1}};
      check(clEnqueueWriteBuffer(d.queue, d.history, CL_TRUE, 0, pixels * sizeof(cl_float4), host.data(), 0, nullptr,
                                 nullptr), "history upload");
    }
    const camera_frame now = make_frame(cam, w, h), before = make_frame(state.cam, w, h);
    const cl_uint still_camera = same_view(cam, state.cam);
    const cl_uint still_gaze = gaze == state.gaze;
    const cl_taa_camera cn = to_cl(now), cb = to_cl(before);
    const cl_int cw = w, ch = h;
    const cl_float gx = float(gaze.x), gy = float(gaze.y), bx = float(state.gaze.x), by = float(state.gaze.y);
    const cl_float width_v = float(double(display.width) * display.viewing_distance);
    cl_uint a = 0;
    auto arg = [&](const auto& value) { check(clSetKernelArg(d.taa, a++, sizeof(value), &value), "clSetKernelArg"); };
    arg(d.out_rgb), arg(d.out_depth), arg(d.history), arg(d.taa_out), arg(cw), arg(ch), arg(cn), arg(cb), arg(still_camera);
    arg(gx), arg(gy), arg(bx), arg(by), arg(still_gaze), arg(width_v), arg(taa.alpha), arg(taa.clip_gamma), arg(taa.focus_lag_deg);
    const cl_float tan_lag = taa.focus_lag_deg < 90 ? std::tan(float(taa.focus_lag_deg * M_PI / 180)) : INFINITY;
    arg(tan_lag);
    const size_t global[2] = {size_t(w), size_t(h)};
    cl_event blended = nullptr;
    check(clEnqueueNDRangeKernel(d.queue, d.taa, 2, nullptr, global, nullptr, 0, nullptr, &blended), "TAA launch");
    check(clWaitForEvents(1, &blended), "TAA wait");
    taa_ms = event_ms(blended);
    clReleaseEvent(blended);
    std::swap(d.history, d.taa_out);  // the output is the next history
  } else {
    check(clEnqueueCopyBuffer(d.queue, d.out_rgb, d.history, 0, 0, pixels * sizeof(cl_float4), 0, nullptr, nullptr),
          "history copy");
  }
  check(clWaitForEvents(1, &done), "kernel wait");
  check(clFinish(d.queue), "history copy");
  result.read_back_ms = read_back(d.history, out);
  result.kernel_ms = event_ms(done);
  result.taa_kernel_ms = taa_ms;
  clReleaseEvent(done);
  taa_remember(state, out, cam, gaze);
  d.history_generation = state.generation;
  return result;
}

const weight_cache* cl_reconstructor::cached_weights() const {
  return impl_->last_weights ? impl_->last_weights->cache.get() : nullptr;
}

size_t cl_reconstructor::weight_caches_held() const { return impl_->caches.size(); }

double cl_reconstructor::copy_gigabytes_per_second(size_t bytes, int repeats) {
  impl& d = *impl_;
  if (!d.ok) return 0;
  const size_t n = std::max<size_t>(1, bytes / 2 / sizeof(cl_float4));  // half read, half written
  cl_int status = 0;
  cl_mem in = clCreateBuffer(d.context, CL_MEM_READ_WRITE, n * sizeof(cl_float4), nullptr, &status);
  check(status, "copy buffer");
  cl_mem out = clCreateBuffer(d.context, CL_MEM_READ_WRITE, n * sizeof(cl_float4), nullptr, &status);
  check(status, "copy buffer");
  const cl_float4 zero = {{0, 0, 0, 0}};
  check(clEnqueueFillBuffer(d.queue, in, &zero, sizeof(zero), 0, n * sizeof(cl_float4), 0, nullptr, nullptr), "fill");
  check(clSetKernelArg(d.copy, 0, sizeof(cl_mem), &in), "clSetKernelArg");
  check(clSetKernelArg(d.copy, 1, sizeof(cl_mem), &out), "clSetKernelArg");
  double best = 1e30;
  for (int r = 0; r < repeats + 1; ++r) {  // the first launch compiles
    cl_event done = nullptr;
    check(clEnqueueNDRangeKernel(d.queue, d.copy, 1, nullptr, &n, nullptr, 0, nullptr, &done), "copy launch");
    check(clWaitForEvents(1, &done), "copy wait");
    if (r > 0) best = std::min(best, event_ms(done));
    clReleaseEvent(done);
  }
  clReleaseMemObject(in);
  clReleaseMemObject(out);
  return 2.0 * double(n) * sizeof(cl_float4) / (best * 1e-3) / 1e9;
}

}  // namespace fov
