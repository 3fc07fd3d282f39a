// FovVideoVDP's cost (measure/fvvdp.h, docs/benchmarks.md): one FOVE-eye image pair
// (1280 x 1440, 22.34 pixels per degree), foveated and non-foveated in the one pass, and
// one frame of a 60 Hz video comparison (two temporal channels, four pyramids) once its
// 250 ms of history is full. Content is synthetic texture plus noise: the cost does not
// depend on it.
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "fov/fvvdp.h"

namespace {

const fov::display_geometry fove{1280, 1440, 1.0};

fov::frame textured(uint32_t seed, float noise) {
  fov::frame f;
  f.width = fove.width, f.height = fove.height;
  std::mt19937 random(seed);
  std::normal_distribution<float> n(0, noise);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const float v = 0.5f + 0.25f * std::sin(0.05f * x) * std::cos(0.07f * y) + n(random);
      f.rgb.emplace_back(v * v);
    }
  return f;
}

void BM_FvvdpImage(benchmark::State& state) {
  const fov::frame ref = textured(1, 0), test = textured(2, 0.03f);
  for (auto _ : state) {
    const fov::fvvdp_result r = fov::fvvdp_image(test, ref, fove, {640, 720});
    benchmark::DoNotOptimize(r.jod);
  }
}
BENCHMARK(BM_FvvdpImage)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(5);

void BM_FvvdpVideoFrame(benchmark::State& state) {
  const fov::frame ref = textured(1, 0), test = textured(2, 0.03f);
  fov::fvvdp metric(fove, 60);
  metric.add(test, ref, {640, 720});
  for (auto _ : state) metric.add(test, ref, {640, 720});
  benchmark::DoNotOptimize(metric.result().jod);
}
BENCHMARK(BM_FvvdpVideoFrame)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(5);

}  // namespace

BENCHMARK_MAIN();
