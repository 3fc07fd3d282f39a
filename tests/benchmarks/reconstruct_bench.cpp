// Reconstruction cost per frame (docs/reconstruction.md; thesis Table 2 remade): NN,
// Shepard and RBF at k = 5, 10, 15, 20 on the FOVE s = 1.0 set (precomputed/, generated
// in memory when missing; FOV_BENCH_SET names another .fovset, table or cells), centred
// gaze, on the OpenCL device (the first platform's first device: PoCL here) and on the C++
// path; then the device's reconstruction followed by TAA, as a live loop runs them.
// Colours are synthetic: the cost does not depend on them. Device setup (kernel build,
// table upload) and RBF's one-time weight solve (weight_cache.h) happen outside the timed
// loop; the solve's time is reported as the counter weights_s. BM_PrecomputeWeights times
// that precomputation for RBF, barycentric and natural (their per-frame cost is RBF's: the
// same weighted-sum kernel over the same k).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include <benchmark/benchmark.h>

#include "fov/cl_reconstruct.h"
#include "fov/knn_table.h"
#include "fov/pointset_io.h"
#include "fov/weight_cache.h"

namespace {

std::string set_path() {
  const char* env = std::getenv("FOV_BENCH_SET");
  return env ? env : FOV_SOURCE_DIR "/precomputed/fove-s1.00.fovset";
}

const fov::pointset& bench_set() {
  static const fov::pointset set = [] {
    if (std::getenv("FOV_BENCH_SET") || std::filesystem::exists(set_path())) return fov::load_pointset(set_path());
    return fov::generate_pointset(fov::spacing_model{}, {}, {});
  }();
  return set;
}

const fov::point_samples& bench_samples() {
  static const fov::point_samples s = [] {
    fov::point_samples out;
    const fov::pointset& set = bench_set();
    out.offset = fov::offset_for_gaze(set.model.display, {0.5 * set.model.display.width, 0.5 * set.model.display.height});
    out.colour.resize(set.points.size());
    out.depth.assign(set.points.size(), 3.0f);
    for (size_t i = 0; i < out.colour.size(); ++i) out.colour[i] = glm::vec3((i % 13) / 13.f, (i % 7) / 7.f, 0.3f);
    return out;
  }();
  return s;
}

fov::cl_reconstructor& device() {
  static fov::cl_reconstructor d(bench_set());
  return d;
}

// args: method (0 nn, 1 shepard, 2 rbf), k, device (1 OpenCL, 0 C++)
void BM_Reconstruct(benchmark::State& state) {
  fov::reconstruct_params rp;
  rp.how = fov::method(state.range(0));
  rp.k = uint32_t(state.range(1));
  const bool on_device = state.range(2) == 1;
  if (on_device && !device().available()) return state.SkipWithError(device().reason().c_str());
  // Warm-up: PoCL compiles for the launch shape; RBF solves its weights once.
  std::unique_ptr<fov::weight_cache> cache;
  if (rp.how == fov::method::rbf && !on_device) {
    cache = std::make_unique<fov::weight_cache>(bench_set(), rp);
    cache->prepare(bench_samples().offset);
    state.counters["weights_s"] = cache->seconds();
  }
  if (on_device) {
    device().run(bench_samples(), rp);
    if (rp.how == fov::method::rbf) state.counters["weights_s"] = device().cached_weights()->seconds();
  }
  bool ran_on_device = false;
  double kernel_ms = 1e30, upload_ms = 0, read_back_ms = 0;
  fov::frame f;  // on the device, reused frame to frame as a live loop does
  for (auto _ : state) {
    if (on_device) {
      const fov::reconstruct_result r = device().run(bench_samples(), rp, f);
      ran_on_device = r.on_device;
      if (ran_on_device) kernel_ms = std::min(kernel_ms, r.kernel_ms);
      upload_ms += r.upload_ms, read_back_ms += r.read_back_ms;
    } else {
      f = fov::reconstruct(bench_set(), bench_samples(), rp, nullptr, cache.get());
    }
    benchmark::DoNotOptimize(f.rgb.data());
  }
  state.counters["on_device"] = ran_on_device ? 1 : 0;
  if (!ran_on_device) return;
  state.counters["upload_ms"] = upload_ms / double(state.iterations());
  state.counters["read_back_ms"] = read_back_ms / double(state.iterations());
  // The least a kernel must move per pixel: k table entries (4 B) and, per neighbour,
  // its colour (16 B), depth (4 B), for Shepard and RBF its position (8 B) and for RBF
  // its weight (4 B); writes 16 + 4 B.
  const fov::display_geometry& d = bench_set().model.display;
  const double per_neighbour = rp.how == fov::method::nn ? 4 + 16 + 4 : rp.how == fov::method::shepard ? 4 + 16 + 4 + 8 : 4 + 16 + 4 + 8 + 4;
  const double bytes = double(d.width) * d.height * (per_neighbour * (rp.how == fov::method::nn ? 1 : rp.k) + 20);
  static const double copy_gbps = device().copy_gigabytes_per_second(size_t(256) << 20);
  const double bound_ms = bytes / (copy_gbps * 1e9) * 1e3;
  state.counters["kernel_ms"] = kernel_ms;
  state.counters["bound_ms"] = bound_ms;
  state.counters["kernel_over_bound"] = kernel_ms / bound_ms;
  state.counters["copy_GBps"] = copy_gbps;
}
BENCHMARK(BM_Reconstruct)
    ->ArgNames({"method", "k", "opencl"})
    ->ArgsProduct({{0, 1, 2}, {5, 10, 15, 20}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Reconstruction and TAA on the device, the frame kept there between them (run_taa), as
// fovview's loop runs them: a still camera, the gaze still (moving 0) or stepping 16 px
// each frame (moving 1, which exercises the kernel's focus-lag path). kernel_ms and
// taa_kernel_ms are the two kernels' best device times; the wall time adds the colour
// upload and the frame's read-back (upload_ms, read_back_ms: their means) and the host's
// copy of the frame as the next history.
// args: method (0 nn, 1 shepard, 2 rbf), k, moving gaze (0, 1)
void BM_ReconstructTaa(benchmark::State& state) {
  fov::reconstruct_params rp;
  rp.how = fov::method(state.range(0));
  rp.k = uint32_t(state.range(1));
  if (!device().available()) return state.SkipWithError(device().reason().c_str());
  const fov::display_geometry& d = bench_set().model.display;
  const fov::camera cam;
  fov::taa_state history;
  fov::frame f;
  int step = 0;
  auto gaze = [&] {
    const double dx = state.range(2) ? 16.0 * (step % 2) : 0.0;
    return fov::gaze_point{0.5 * d.width + dx, 0.5 * d.height};
  };
  device().run_taa(bench_samples(), rp, history, cam, gaze(), {}, f);  // warm-up, makes the history
  double kernel_ms = 1e30, taa_ms = 1e30, upload_ms = 0, read_back_ms = 0;
  bool ran_on_device = true;
  for (auto _ : state) {
    ++step;
    const fov::reconstruct_result r = device().run_taa(bench_samples(), rp, history, cam, gaze(), {}, f);
    ran_on_device = ran_on_device && r.on_device;
    kernel_ms = std::min(kernel_ms, r.kernel_ms);
    taa_ms = std::min(taa_ms, r.taa_kernel_ms);
    upload_ms += r.upload_ms, read_back_ms += r.read_back_ms;
    benchmark::DoNotOptimize(f.rgb.data());
  }
  state.counters["on_device"] = ran_on_device ? 1 : 0;
  state.counters["kernel_ms"] = kernel_ms;
  state.counters["taa_kernel_ms"] = taa_ms;
  state.counters["upload_ms"] = upload_ms / double(state.iterations());
  state.counters["read_back_ms"] = read_back_ms / double(state.iterations());
}
BENCHMARK(BM_ReconstructTaa)
    ->ArgNames({"method", "k", "moving"})
    ->ArgsProduct({{0, 1, 2}, {5}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Precomputing the geometry-only weights (weight_cache.h) for a centred screen: RBF's solves,
// and for barycentric and natural the set's Delaunay triangulation (CGAL) plus each canvas
// pixel's weights, from a fresh cache every iteration. Counters: triangulation_s (its part of
// the time), triangulation_MB and cache_MB (the data held: the triangulation's records and
// the computed tiles' weights, 4k bytes per canvas pixel), tiles, and fallback_share (pixels
// that took Shepard's weights, by the method's rules in reconstruct.h).
// args: method (2 rbf, 3 barycentric, 4 natural), k
void BM_PrecomputeWeights(benchmark::State& state) {
  fov::reconstruct_params rp;
  rp.how = fov::method(state.range(0));
  rp.k = uint32_t(state.range(1));
  double triangulation_s = 0, triangulation_mb = 0, cache_mb = 0, tiles = 0, fallback_share = 0;
  for (auto _ : state) {
    fov::weight_cache cache(bench_set(), rp);
    triangulation_s = cache.seconds();
    cache.prepare(bench_samples().offset);
    triangulation_mb = cache.triangulation_bytes() / 1e6;
    tiles = double(cache.tiles_ready());
    cache_mb = tiles * cache.tile_floats() * sizeof(float) / 1e6;
    fallback_share = double(cache.stats().fallbacks) / double(std::max<uint64_t>(1, cache.stats().pixels));
  }
  state.counters["triangulation_s"] = triangulation_s;
  state.counters["triangulation_MB"] = triangulation_mb;
  state.counters["cache_MB"] = cache_mb;
  state.counters["tiles"] = tiles;
  state.counters["fallback_share"] = fallback_share;
}
BENCHMARK(BM_PrecomputeWeights)
    ->ArgNames({"method", "k"})
    ->ArgsProduct({{2, 3, 4}, {5, 8, 12, 20}})
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

// The set and the device go into the report's context, so a run on another machine says
// what it measured.
int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    bench_set();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reconstruct_bench: %s: %s\n", set_path().c_str(), e.what());
    return 2;
  }
  const fov::pointset& set = bench_set();
  benchmark::AddCustomContext("set", set_path() + (std::filesystem::exists(set_path()) ? "" : " (generated in memory)"));
  benchmark::AddCustomContext("display", std::to_string(set.model.display.width) + "x" + std::to_string(set.model.display.height));
  benchmark::AddCustomContext("points", std::to_string(set.points.size()));
  benchmark::AddCustomContext("opencl_device", device().available() ? device().device() : "none: " + device().reason());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
