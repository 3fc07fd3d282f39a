// Tracer throughput (docs/benchmarks.md):
//  - the tracer's rays per second against a bare Embree loop casting the same recorded rays
//    in the same way (BM_TracerAgainstBareLoop: direct and path-traced, the room and the helmet);
//  - the full tracer (ray generation, intersection, shading, shadow rays) against a
//    bare Embree loop over pixel-centre rays at 1280x1440, and over the same foveated
//    rays trace_points casts (BM_BareEmbreeSameRays);
//  - a foveated frame (trace_points, centred gaze) against the full-resolution
//    reference at equal rays per sample, for point sets s = 1.0 and 1.75.
// Scenes: builtin, ../shared/scenes/flight-helmet when present, and a generated env:
// image whose rays all cost the same (it separates the tracer's own overhead from the
// content under the fovea, which differs between foveated and reference rays). Point sets come
// from precomputed/fove-s1.00.fovset and fove-s1.75.fovset (and their --fovea grid twins
// fove-s1.00-grid.fovset, fove-s1.75-grid.fovset), generated in memory if missing.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>

#include <benchmark/benchmark.h>
#include <OpenImageIO/imageio.h>
#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "../../tracer/src/scene_impl.h"
#include "fov/knn_table.h"
#include "fov/pointset_io.h"
#include "fov/trace.h"

namespace {

namespace fs = std::filesystem;
constexpr int width = 1280, height = 1440;

fov::trace_params with_k(fov::trace_params p, uint32_t k) {
  p.k = k;
  return p;
}

// A 2048x1024 lat-long image of smooth colour bands: an env: scene in which every ray
// costs the same (one filtered lookup), so foveated and reference rays compare fairly.
std::string uniform_cost_envmap() {
  const std::string path = (fs::temp_directory_path() / "fovray-bench-env.exr").string();
  const int w = 2048, h = 1024;
  std::vector<float> px(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        px[(size_t(y) * w + x) * 3 + c] = 0.5f + 0.5f * std::sin(0.05f * float(x * (c + 1)) + 0.03f * float(y));
  auto out = OIIO::ImageOutput::create(path);
  out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
  out->write_image(OIIO::TypeDesc::FLOAT, px.data());
  out->close();
  return "env:" + path;
}

// Scenes 0 = built-in, 1 = flight helmet (skipped when absent), 2 = uniform-cost env: image,
// 3 = the built-in room (builtin:cornell).
const std::vector<std::string>& scene_specs() {
  static const std::vector<std::string> specs = [] {
    const fs::path helmet = fs::path(FOV_SOURCE_DIR) / "../shared/scenes/flight-helmet/FlightHelmet.gltf";
    return std::vector<std::string>{"builtin", fs::exists(helmet) ? helmet.string() : "", uniform_cost_envmap(),
                                    "builtin:cornell"};
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
    fov::trace_reference(*s, s->default_camera(90), width, height, tp).image;
  }
  return *s;
}

fov::camera bench_camera(const fov::scene& s) { return s.default_camera(90); }

// The traced-point index of a set for k = 5, as the renderer keeps it (built once).
const fov::traced_index& get_index(const fov::pointset& set) {
  static std::map<const fov::pointset*, fov::traced_index> indexes;
  auto it = indexes.find(&set);
  if (it == indexes.end()) it = indexes.emplace(&set, fov::make_traced_index(set, 5)).first;
  return it->second;
}

const fov::pointset& get_set(double scale, bool grid = false) {
  static std::map<std::pair<double, bool>, fov::pointset> sets;
  auto it = sets.find({scale, grid});
  if (it != sets.end()) return it->second;
  const fs::path file =
      fs::path(FOV_SOURCE_DIR) / fmt::format("precomputed/fove-s{:.2f}{}.fovset", scale, grid ? "-grid" : "");
  if (fs::exists(file)) return sets[{scale, grid}] = fov::load_pointset(file.string());
  fov::spacing_model m;
  m.scale = scale;
  fov::dart_params darts;
  if (grid) darts.fovea = fov::fovea_layout::grid;
  return sets[{scale, grid}] = fov::generate_pointset(m, darts, {});
}

// Intersects one packet of primary rays through screen positions at[0, n), n <= 16, and
// nothing else: what the bare loops below time.
void intersect_packet(RTCScene top, const fov::camera_frame& f, const glm::vec2* at, int n) {
  RTCIntersectContext ctx;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  for (int i = 0; i < 16; ++i) {
    const glm::vec2 p = at[std::min(i, n - 1)];
    const glm::vec3 d = fov::ray_direction(f, p.x, p.y);
    valid[i] = i < n ? -1 : 0;
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

// Primary rays through pixel centres, packets of 16 over 4x4 pixel blocks: intersection only.
void BM_BareEmbree(benchmark::State& state) {
  if (scene_specs().at(size_t(state.range(0))).empty()) return state.SkipWithError("scene absent");
  if (state.range(0) == 2) return state.SkipWithError("an env: scene has no geometry to intersect");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  const fov::camera_frame f = fov::make_frame(bench_camera(s), width, height);
  RTCScene top = s.internals().top;
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height / 4), [&](const tbb::blocked_range<int>& rows) {
      glm::vec2 at[16];
      for (int by = rows.begin(); by < rows.end(); ++by)
        for (int bx = 0; bx < width / 4; ++bx) {
          for (int i = 0; i < 16; ++i) at[i] = {float(bx * 4 + i % 4) + 0.5f, float(by * 4 + i / 4) + 0.5f};
          intersect_packet(top, f, at, 16);
        }
    });
  }
  state.counters["Mrays/s"] = benchmark::Counter(double(width) * height * state.iterations() / 1e6, benchmark::Counter::kIsRate);
  state.counters["isect_Mrays_per_thread_s"] = benchmark::Counter(
      double(width) * height * state.iterations() / 1e6 / tbb::this_task_arena::max_concurrency(), benchmark::Counter::kIsRate);
}

// args: scene, spp, scale x 100. The rays a foveated frame casts (trace_points at the
// centred gaze reading all k neighbours, as BM_TracePoints), intersected and nothing
// else: packets of 16 in the tracer's order, split over threads in tasks of 256 rays as
// the tracer splits them. The bare loop the intersection goal is measured against for
// foveated rays, which are sparser, so less coherent, than pixel-centre rays.
void BM_BareEmbreeSameRays(benchmark::State& state) {
  if (scene_specs().at(size_t(state.range(0))).empty()) return state.SkipWithError("scene absent");
  if (state.range(0) == 2) return state.SkipWithError("an env: scene has no geometry to intersect");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  const fov::pointset& set = get_set(double(state.range(2)) / 100);
  fov::trace_params tp;
  tp.spp = uint32_t(state.range(1));
  const fov::point_samples traced = fov::trace_points(s, bench_camera(s), set, {width / 2.0, height / 2.0}, with_k(tp, set.table.k)).samples;
  const std::vector<glm::vec2> at = fov::point_ray_positions(set, traced, {width / 2.0, height / 2.0}, tp);
  const fov::camera_frame f = fov::make_frame(bench_camera(s), width, height);
  RTCScene top = s.internals().top;
  const size_t task = std::max<size_t>(1, 256 / tp.spp) * tp.spp;
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, (at.size() + task - 1) / task), [&](const tbb::blocked_range<size_t>& tasks) {
      for (size_t t = tasks.begin(); t < tasks.end(); ++t)
        for (size_t base = t * task, end = std::min(at.size(), base + task); base < end; base += 16)
          intersect_packet(top, f, at.data() + base, int(std::min<size_t>(16, end - base)));
    });
  }
  const double rays = double(at.size()) * double(state.iterations());
  state.counters["rays"] = double(at.size());
  state.counters["Mrays/s"] = benchmark::Counter(rays / 1e6, benchmark::Counter::kIsRate);
  state.counters["isect_Mrays_per_thread_s"] =
      benchmark::Counter(rays / 1e6 / tbb::this_task_arena::max_concurrency(), benchmark::Counter::kIsRate);
}

// Runs `trace` once more with stage timing on and reports nanoseconds of thread time per
// ray for each stage (the timed iterations above it run without the clock reads).
template <class Trace>
void report_stages(benchmark::State& state, Trace&& trace) {
  const auto [ray_count, t] = trace();  // (rays, trace_stats::timing) of a trace with time_stages on
  const double rays = double(ray_count);
  state.counters["setup_ns"] = 1e9 * t.setup / rays;
  state.counters["intersect_ns"] = 1e9 * t.intersect / rays;
  state.counters["shade_ns"] = 1e9 * t.shade / rays;
  state.counters["shadow_ns"] = 1e9 * t.shadow / rays;
  state.counters["isect_Mrays_per_thread_s"] = rays / t.intersect / 1e6;
}

// args: scene, spp
void BM_TraceReference(benchmark::State& state) {
  if (scene_specs().at(size_t(state.range(0))).empty()) return state.SkipWithError("scene absent");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  fov::trace_params tp;
  tp.spp = uint32_t(state.range(1));
  uint64_t rays = 0;
  for (auto _ : state) rays += fov::trace_reference(s, bench_camera(s), width, height, tp).image.rays;
  state.counters["Mrays/s"] = benchmark::Counter(double(rays) / 1e6, benchmark::Counter::kIsRate);
  state.counters["rays"] = double(rays) / double(state.iterations());
  report_stages(state, [&] {
    tp.time_stages = true;
    const fov::reference_trace r = fov::trace_reference(s, bench_camera(s), width, height, tp);
    return std::make_pair(r.image.rays, r.stats.timing);
  });
}

// args: scene, spp, scale x 100
void BM_TracePoints(benchmark::State& state) {
  if (scene_specs().at(size_t(state.range(0))).empty()) return state.SkipWithError("scene absent");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  const fov::pointset& set = get_set(double(state.range(2)) / 100);
  fov::trace_params tp;
  tp.spp = uint32_t(state.range(1));
  uint64_t rays = 0;
  for (auto _ : state) rays += fov::trace_points(s, bench_camera(s), set, {width / 2.0, height / 2.0}, with_k(tp, set.table.k)).samples.rays;
  state.counters["Mrays/s"] = benchmark::Counter(double(rays) / 1e6, benchmark::Counter::kIsRate);
  state.counters["rays"] = double(rays) / double(state.iterations());
  report_stages(state, [&] {
    tp.time_stages = true;
    const fov::points_trace r = fov::trace_points(s, bench_camera(s), set, {width / 2.0, height / 2.0}, with_k(tp, set.table.k));
    return std::make_pair(r.samples.rays, r.stats.timing);
  });
}

// args: scene, gaze (0 centre, 1 top-left corner, 2 bottom-right corner); 4 spp, s = 1.0.
// Where the fovea lands changes what the dense rays see, and so their shading cost.
void BM_TracePointsByGaze(benchmark::State& state) {
  if (scene_specs().at(size_t(state.range(0))).empty()) return state.SkipWithError("scene absent");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  const fov::pointset& set = get_set(1.0);
  const double gx[3] = {width / 2.0, 0, double(width)}, gy[3] = {height / 2.0, 0, double(height)};
  const int g = int(state.range(1));
  fov::trace_params tp;
  tp.spp = 4;
  uint64_t rays = 0;
  for (auto _ : state) rays += fov::trace_points(s, bench_camera(s), set, {gx[g], gy[g]}, with_k(tp, set.table.k)).samples.rays;
  state.counters["rays"] = double(rays) / double(state.iterations());
  report_stages(state, [&] {
    tp.time_stages = true;
    const fov::points_trace r = fov::trace_points(s, bench_camera(s), set, {gx[g], gy[g]}, with_k(tp, set.table.k));
    return std::make_pair(r.samples.rays, r.stats.timing);
  });
}
// args: scene, spp, scale x 100, pixel footprint (0: disc, the default; 1: pixel; see
// fov::texture_footprint), grid (0: the thesis's darts, 1: fovgen --fovea grid). Foveated and reference frames traced in turn, each
// iteration; counters are medians over iterations. The plain goal compares the foveated
// frame's time with its share of the reference's rays (ray_over_time: ray ratio / time
// ratio). Rays do not all cost the same, and foveated rays crowd under the gaze, so the
// content-weighted ratio prices each traced point's rays at what the reference's rays
// cost in the 8 x 8-pixel tile where the point lies (trace_params::tile_costs):
// content_over_time (content-weighted ratio / time ratio) is the tracer's own overhead
// for foveated tracing, with the scene's uneven cost taken out.
void BM_ContentWeightedRatio(benchmark::State& state) {
  if (scene_specs().at(size_t(state.range(0))).empty()) return state.SkipWithError("scene absent");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  const fov::pointset& set = get_set(double(state.range(2)) / 100, state.range(4) != 0);
  const fov::display_geometry& d = set.model.display;
  fov::trace_params tp;
  tp.spp = uint32_t(state.range(1));
  if (state.range(3)) tp.footprint = fov::texture_footprint::pixel;  // foveated rays filtered as the reference's
  using clock = std::chrono::steady_clock;
  auto ms_since = [](clock::time_point t) { return std::chrono::duration<double, std::milli>(clock::now() - t).count(); };
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  std::vector<double> fov_ms, ref_ms, content;
  double ray_ratio = 0;
  for (auto _ : state) {
    auto t0 = clock::now();
    const fov::point_samples samples =
        fov::trace_points(s, bench_camera(s), set, get_index(set), {d.width / 2.0, d.height / 2.0}, with_k(tp, 5)).samples;
    fov_ms.push_back(ms_since(t0));
    fov::trace_params rp = tp;
    rp.tile_costs = true;
    t0 = clock::now();
    const fov::reference_trace traced = fov::trace_reference(s, bench_camera(s), d.width, d.height, rp);
    ref_ms.push_back(ms_since(t0));
    const fov::frame& reference = traced.image;
    const std::vector<double>& tiles = traced.stats.tile_seconds;
    ray_ratio = double(samples.rays) / double(reference.rays);
    // Each traced point's rays at the per-ray cost of the reference tile it lies in
    // (points off the screen: the nearest tile).
    const int t = fov::reference_tile, tiles_x = (d.width + t - 1) / t;
    double predicted = 0, total = 0;
    for (double v : tiles) total += v;
    for (uint32_t i : samples.traced) {
      const fov::point& p = set.points[i];
      const int x = std::clamp(int(p.x) - samples.offset.x, 0, d.width - 1);
      const int y = std::clamp(int(p.y) - samples.offset.y, 0, d.height - 1);
      const int tx = x / t, ty = y / t;
      const int tile_pixels = (std::min(d.width, tx * t + t) - tx * t) * (std::min(d.height, ty * t + t) - ty * t);
      predicted += tiles[size_t(ty) * tiles_x + tx] / tile_pixels;  // per point: spp rays at the tile's per-pixel cost
    }
    content.push_back(predicted / total);
  }
  const double time_ratio = median(fov_ms) / median(ref_ms);
  state.counters["foveated_ms"] = median(fov_ms);
  state.counters["reference_ms"] = median(ref_ms);
  state.counters["ray_ratio"] = ray_ratio;
  state.counters["content_ratio"] = median(content);
  state.counters["time_ratio"] = time_ratio;
  state.counters["ray_over_time"] = ray_ratio / time_ratio;
  state.counters["content_over_time"] = median(content) / time_ratio;
}
// Casts recorded rays (trace_params::record_rays) the way the tracer cast them and does
// nothing else: primary rays in the same packets of 16 (coherent), a packet's shadow rays
// towards a light as one packet, bounce and path-vertex shadow rays one at a time.
void cast_recorded(RTCScene top, const std::vector<fov::recorded_ray>& rays) {
  using kind = fov::recorded_ray::kind;
  RTCIntersectContext ctx;
  for (size_t i = 0; i < rays.size();) {
    const fov::recorded_ray& r = rays[i];
    if (r.how == kind::bounce || r.how == kind::shadow) {
      RTCRayHit rh;
      rh.ray.org_x = r.origin.x, rh.ray.org_y = r.origin.y, rh.ray.org_z = r.origin.z;
      rh.ray.dir_x = r.dir.x, rh.ray.dir_y = r.dir.y, rh.ray.dir_z = r.dir.z;
      rh.ray.tnear = 0, rh.ray.tfar = r.tfar, rh.ray.time = 0;
      rh.ray.mask = ~0u, rh.ray.id = 0, rh.ray.flags = 0;
      rh.hit.geomID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcInitIntersectContext(&ctx);
      if (r.how == kind::bounce) {
        rtcIntersect1(top, &ctx, &rh);
        benchmark::DoNotOptimize(rh.hit.primID);
      } else {
        rtcOccluded1(top, &ctx, &rh.ray);
        benchmark::DoNotOptimize(rh.ray.tfar);
      }
      ++i;
      continue;
    }
    size_t n = 1;
    while (i + n < rays.size() && n < 16 && rays[i + n].how == r.how && !rays[i + n].starts_packet) ++n;
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    for (size_t l = 0; l < 16; ++l) {
      const fov::recorded_ray& q = rays[i + std::min(l, n - 1)];
      valid[l] = l < n ? -1 : 0;
      rh.ray.org_x[l] = q.origin.x, rh.ray.org_y[l] = q.origin.y, rh.ray.org_z[l] = q.origin.z;
      rh.ray.dir_x[l] = q.dir.x, rh.ray.dir_y[l] = q.dir.y, rh.ray.dir_z[l] = q.dir.z;
      rh.ray.tnear[l] = 0, rh.ray.tfar[l] = q.tfar, rh.ray.time[l] = 0;
      rh.ray.mask[l] = ~0u, rh.ray.id[l] = unsigned(l), rh.ray.flags[l] = 0;
      rh.hit.geomID[l] = rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcInitIntersectContext(&ctx);
    if (r.how == kind::primary) {
      ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      rtcIntersect16(valid, top, &ctx, &rh);
      benchmark::DoNotOptimize(rh.hit.primID[0]);
    } else {
      rtcOccluded16(valid, top, &ctx, &rh.ray);
      benchmark::DoNotOptimize(rh.ray.tfar[0]);
    }
    i += n;
  }
}

// args: scene, integrator (0: direct; 1 + N: path with N bounces). The
// tracer's rays per second against a bare Embree loop over the same rays (issue 29's speed
// goal: path-traced rays at >= 70 % of the bare loop's rate). One full-resolution frame at
// 1 spp is traced once with its rays recorded; then each iteration traces it again (not
// recording) and casts the recorded rays in the bare loop, split over threads by the
// tracer's own tasks, in turn. bare_share = bare time / trace time per iteration (the
// tracer's rate as a share of the bare loop's, for the same rays): median, min and max.
void BM_TracerAgainstBareLoop(benchmark::State& state) {
  if (scene_specs().at(size_t(state.range(0))).empty()) return state.SkipWithError("scene absent");
  const fov::scene& s = get_scene(size_t(state.range(0)));
  fov::trace_params tp;
  tp.spp = 1;
  if (state.range(1) > 0) tp.method = fov::integrator::path, tp.bounces = uint32_t(state.range(1) - 1);
  tp.record_rays = true;
  const fov::reference_trace recorded = fov::trace_reference(s, bench_camera(s), width, height, tp);
  tp.record_rays = false;
  const std::vector<std::vector<fov::recorded_ray>>& tasks = recorded.stats.recorded;
  RTCScene top = s.internals().top;
  using clock = std::chrono::steady_clock;
  auto ms_since = [](clock::time_point t) { return std::chrono::duration<double, std::milli>(clock::now() - t).count(); };
  std::vector<double> trace_ms, bare_ms, share;
  for (auto _ : state) {
    auto t0 = clock::now();
    benchmark::DoNotOptimize(fov::trace_reference(s, bench_camera(s), width, height, tp).image.rgb.data());
    trace_ms.push_back(ms_since(t0));
    t0 = clock::now();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tasks.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t t = r.begin(); t < r.end(); ++t) cast_recorded(top, tasks[t]);
    });
    bare_ms.push_back(ms_since(t0));
    share.push_back(bare_ms.back() / trace_ms.back());
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  const fov::ray_counts& c = recorded.stats.cast;
  const double rays = double(c.total());
  state.counters["rays_M"] = rays / 1e6;
  state.counters["primary_share"] = double(c.primary) / rays;
  state.counters["shadow_share"] = double(c.shadow) / rays;
  state.counters["bounce_share"] = double(c.bounce) / rays;
  state.counters["trace_ms"] = median(trace_ms);
  state.counters["bare_ms"] = median(bare_ms);
  state.counters["trace_Mrays_s"] = rays / 1e3 / median(trace_ms);
  state.counters["bare_Mrays_s"] = rays / 1e3 / median(bare_ms);
  state.counters["bare_share"] = median(share);
  state.counters["bare_share_min"] = *std::min_element(share.begin(), share.end());
  state.counters["bare_share_max"] = *std::max_element(share.begin(), share.end());
  // Where the tracer's time goes (thread-ms of one more trace with stage timing on).
  tp.time_stages = true;
  const fov::trace_timing t = fov::trace_reference(s, bench_camera(s), width, height, tp).stats.timing;
  state.counters["setup_tms"] = 1e3 * t.setup;
  state.counters["intersect_tms"] = 1e3 * t.intersect;
  state.counters["shade_tms"] = 1e3 * t.shade;
  state.counters["shadow_tms"] = 1e3 * t.shadow;
  state.counters["bounce_tms"] = 1e3 * t.bounce;
  state.counters["bounce_rays_tms"] = 1e3 * t.bounce_rays;
}
// integrator argument: 0 = direct, 1 + N = path with N bounces.
BENCHMARK(BM_TracerAgainstBareLoop)
    ->ArgNames({"scene", "integrator"})
    ->ArgsProduct({{3, 1}, {0, 1, 2, 4}})
    ->Iterations(7)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(BM_ContentWeightedRatio)
    ->ArgNames({"scene", "spp", "s100", "pixel_footprint", "grid"})
    ->ArgsProduct({{0, 1, 2}, {1, 4, 32}, {100, 175}, {0}, {0, 1}})
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// The helmet's foveated rays with the reference's texture filter width: what is left of
// its overhead once wider filters (two MIP levels where the reference magnifies) are out.
BENCHMARK(BM_ContentWeightedRatio)
    ->ArgNames({"scene", "spp", "s100", "pixel_footprint", "grid"})
    ->ArgsProduct({{1}, {4, 32}, {100, 175}, {1}, {0}})
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(BM_TracePointsByGaze)->ArgNames({"scene", "gaze"})->ArgsProduct({{0, 1}, {0, 1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK(BM_BareEmbree)->ArgName("scene")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BareEmbreeSameRays)
    ->ArgNames({"scene", "spp", "s100"})
    ->ArgsProduct({{0, 1}, {4, 32}, {100, 175}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_TraceReference)->ArgNames({"scene", "spp"})->ArgsProduct({{0, 1, 2}, {1, 4, 32}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TracePoints)->ArgNames({"scene", "spp", "s100"})->ArgsProduct({{0, 1, 2}, {4, 32}, {100, 175}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
