// Tracer throughput (docs/benchmarks.md):
//  - the full tracer (ray generation, intersection, shading, shadow rays) against a
//    bare Embree loop over the same primary rays, at 1280x1440 and 1 ray per pixel;
//  - a foveated frame (trace_points, centred gaze) against the full-resolution
//    reference at equal rays per sample, for point sets s = 1.0 and 1.75.
// Scenes: builtin, and ../shared/scenes/flight-helmet when present. Point sets come
// from precomputed/fove-s1.00.fovset and fove-s1.75.fovset, generated in memory if missing.
#include <filesystem>
#include <map>

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "../../tracer/src/scene_impl.h"
#include "fov/knn_table.h"
#include "fov/pointset_io.h"
#include "fov/trace.h"

namespace {

namespace fs = std::filesystem;
constexpr int width = 1280, height = 1440;

const std::vector<std::string>& scene_specs() {
  static const std::vector<std::string> specs = [] {
    std::vector<std::string> s{"builtin"};
    const fs::path helmet = fs::path(FOV_SOURCE_DIR) / "../shared/scenes/flight-helmet/FlightHelmet.gltf";
    if (fs::exists(helmet)) s.push_back(helmet.string());
    return s;
  }();
  return specs;
}

const fov::scene& get_scene(size_t i) {
  static std::map<size_t, std::unique_ptr<fov::scene>> scenes;
  auto& s = scenes[i];
  if (!s) {
    s = fov::load_scene(scene_specs().at(i));
    // Warm-up, untimed: OpenImageIO builds MIP levels on first use of each texture.
    fov::trace_params tp;
    tp.spp = 1;
    fov::trace_reference(*s, s->default_camera(90), width, height, tp);
  }
  return *s;
}

fov::camera bench_camera(const fov::scene& s) { return s.default_camera(90); }

const fov::pointset& get_set(double scale) {
  static std::map<double, fov::pointset> sets;
  auto it = sets.find(scale);
  if (it != sets.end()) return it->second;
  const fs::path file = fs::path(FOV_SOURCE_DIR) / fmt::format("precomputed/fove-s{:.2f}.fovset", scale);
  if (fs::exists(file)) return sets[scale] = fov::load_pointset(file.string());
  fov::spacing_model m;
  m.scale = scale;
  return sets[scale] = fov::generate_pointset(m, {}, {});
}

// Primary rays through pixel centres, packets of 16 over 4x4 pixel blocks: intersection only.
void BM_BareEmbree(benchmark::State& state) {
  if (size_t(state.range(0)) >= scene_specs().size()) return state.SkipWithError("scene absent");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  const fov::camera_frame f = fov::make_frame(bench_camera(s), width, height);
  RTCScene top = s.internals().top;
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height / 4), [&](const tbb::blocked_range<int>& rows) {
      RTCIntersectContext ctx;
      alignas(64) RTCRayHit16 rh;
      alignas(64) int valid[16];
      for (int by = rows.begin(); by < rows.end(); ++by)
        for (int bx = 0; bx < width / 4; ++bx) {
          for (int i = 0; i < 16; ++i) {
            const glm::vec3 d = fov::ray_direction(f, float(bx * 4 + i % 4) + 0.5f, float(by * 4 + i / 4) + 0.5f);
            valid[i] = -1;
            rh.ray.org_x[i] = f.origin.x, rh.ray.org_y[i] = f.origin.y, rh.ray.org_z[i] = f.origin.z;
            rh.ray.dir_x[i] = d.x, rh.ray.dir_y[i] = d.y, rh.ray.dir_z[i] = d.z;
            rh.ray.tnear[i] = 0, rh.ray.tfar[i] = INFINITY, rh.ray.time[i] = 0;
            rh.ray.mask[i] = ~0u, rh.ray.id[i] = unsigned(i), rh.ray.flags[i] = 0;
            rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
          }
          rtcInitIntersectContext(&ctx);
          ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
          rtcIntersect16(valid, top, &ctx, &rh);
          benchmark::DoNotOptimize(rh.hit.primID[0]);
        }
    });
  }
  state.counters["Mrays/s"] = benchmark::Counter(double(width) * height * state.iterations() / 1e6, benchmark::Counter::kIsRate);
}

// args: scene, spp
void BM_TraceReference(benchmark::State& state) {
  if (size_t(state.range(0)) >= scene_specs().size()) return state.SkipWithError("scene absent");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  fov::trace_params tp;
  tp.spp = uint32_t(state.range(1));
  uint64_t rays = 0;
  for (auto _ : state) rays += fov::trace_reference(s, bench_camera(s), width, height, tp).rays;
  state.counters["Mrays/s"] = benchmark::Counter(double(rays) / 1e6, benchmark::Counter::kIsRate);
  state.counters["rays"] = double(rays) / double(state.iterations());
}

// args: scene, spp, scale x 100
void BM_TracePoints(benchmark::State& state) {
  if (size_t(state.range(0)) >= scene_specs().size()) return state.SkipWithError("scene absent");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  const fov::pointset& set = get_set(double(state.range(2)) / 100);
  fov::trace_params tp;
  tp.spp = uint32_t(state.range(1));
  uint64_t rays = 0;
  for (auto _ : state) rays += fov::trace_points(s, bench_camera(s), set, width / 2.0, height / 2.0, set.table.k, tp).rays;
  state.counters["Mrays/s"] = benchmark::Counter(double(rays) / 1e6, benchmark::Counter::kIsRate);
  state.counters["rays"] = double(rays) / double(state.iterations());
}

BENCHMARK(BM_BareEmbree)->ArgName("scene")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TraceReference)->ArgNames({"scene", "spp"})->ArgsProduct({{0, 1}, {1, 4}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TracePoints)->ArgNames({"scene", "spp", "s100"})->ArgsProduct({{0, 1}, {4}, {100, 175}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
