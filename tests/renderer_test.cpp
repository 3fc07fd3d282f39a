// The one frame pipeline every tool drives (fov::renderer): it must give what the library
// calls it stands for give, honour the camera overrides for every scene kind, follow the
// ray pattern under TAA, trace ahead without ever showing a stale frame, and the flicker
// experiment built on it must measure what it says.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include "fov/dart_throwing.h"
#include "fov/flicker.h"
#include "fov/knn_table.h"
#include "fov/metrics.h"
#include "fov/renderer.h"
#include "fov/speedup.h"
#include "fov/stereo_renderer.h"
#include "fov/usage_error.h"
#include "opencl_required.h"
#include "test_sets.h"

namespace fov {
namespace {

namespace fs = std::filesystem;

std::shared_ptr<const pointset> small_set(int w = 64, int h = 48) {
  auto set = std::make_shared<pointset>();
  set->model.display = {w, h, 1.0};
  set->points = throw_darts(set->model, {});
  knn_params kp;
  kp.k = 8;
  set->table = build_knn_table(set->points, set->canvas_width(), set->canvas_height(), kp);
  set_knn_radii(set->table, set->points);
  return set;
}

float max_difference(const frame& a, const frame& b) {
  EXPECT_EQ(a.rgb.size(), b.rgb.size());
  float m = 0;
  for (size_t i = 0; i < a.rgb.size() && i < b.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) m = std::max(m, std::fabs(a.rgb[i][c] - b.rgb[i][c]));
  return m;
}

double mean_abs(const frame& a, const frame& b) {
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) sum += std::fabs(a.rgb[i][c] - b.rgb[i][c]);
  return sum / double(3 * a.rgb.size());
}

// A camera path that moves 20 units along x from 100 to 120 ms, looking down -z throughout.
std::shared_ptr<const camera_path> sideways_path() {
  auto path = std::make_shared<camera_path>();
  path->keys = {{100, {0, 0, 0}, {0, 0, -1}}, {120, {20, 0, 0}, {20, 0, -1}}};
  return path;
}

// A small lat-long image with a horizontal ramp: an env: scene whose camera has its own
// field of view (90 degrees), like the built-in scene's and a file camera's.
std::string ramp_envmap() {
  const std::string path = (fs::path(::testing::TempDir()) / "fovray-renderer-env.exr").string();
  const int w = 256, h = 128;
  std::vector<float> px(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) px[(size_t(y) * w + x) * 3 + c] = float(x) / w * (c + 1) / 3.0f + float(y) / h * 0.2f;
  auto out = OIIO::ImageOutput::create(path);
  out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
  out->write_image(OIIO::TypeDesc::FLOAT, px.data());
  out->close();
  return "env:" + path;
}

struct pipeline : ::testing::Test {
  std::shared_ptr<const scene> scn = load_scene("builtin");
  std::shared_ptr<const pointset> set = small_set();
  render_params params;
  void SetUp() override {
    params.spp = 2;
    params.taa = false;  // a fixed ray pattern: each frame depends on gaze and camera only
    params.reconstruct.k = 5;
    params.device = reconstruct_device::cpp;
  }
};

TEST_F(pipeline, AFrameIsTheTraceAndReconstructionItStandsFor) {
  renderer r(scn, params);
  r.use_pointset(set);
  const gaze_point g{20, 30};
  frame_timing t;
  const frame got = r.foveated(g, params, &t);
  trace_params tp;
  tp.spp = params.spp;
  tp.k = params.reconstruct.k;
  const points_trace direct = trace_points(*scn, setup_camera(*scn), *set, g, tp);
  const frame expected = reconstruct(*set, direct.samples, params.reconstruct);
  EXPECT_EQ(max_difference(got, expected), 0.0f);
  EXPECT_EQ(t.rays, direct.samples.rays);
  EXPECT_EQ(t.cast.primary, direct.samples.rays);
  EXPECT_EQ(t.cast.shadow, direct.stats.cast.shadow);
  EXPECT_GT(t.cast.shadow, 0u);  // the sun lights the scene
  EXPECT_EQ(t.cast.bounce, 0u);  // the direct integrator
  EXPECT_EQ(t.points_traced, direct.samples.traced.size());
  EXPECT_GT(t.trace_ms, 0.0);
  EXPECT_GT(t.reconstruct_ms, 0.0);
  EXPECT_EQ(t.taa_ms, 0.0);  // no TAA asked for
  EXPECT_DOUBLE_EQ(t.total_ms(), t.trace_ms + t.reconstruct_ms);
  // The reference is the library's too.
  const frame ref = r.reference(64, 48, params).image;
  EXPECT_EQ(max_difference(ref, trace_reference(*scn, setup_camera(*scn), 64, 48, tp).image), 0.0f);
  // A path-traced full grid reports its bounces and every kind of ray as the library counts them.
  render_params path = params;
  path.method = integrator::path, path.bounces = 2;
  frame_timing pt;
  r.reference(64, 48, path, &pt);
  tp.method = integrator::path, tp.bounces = 2;
  const ray_counts library = trace_reference(*scn, setup_camera(*scn), 64, 48, tp).stats.cast;
  EXPECT_EQ(pt.cast.primary, 64u * 48u * params.spp);
  EXPECT_GT(pt.cast.bounce, 0u);
  EXPECT_EQ(pt.cast.bounce, library.bounce);
  EXPECT_EQ(pt.cast.shadow, library.shadow);
}

TEST_F(pipeline, CameraOverridesApplyToEverySceneKind) {
  const std::string env = ramp_envmap();
  for (const std::string& spec : {std::string("builtin"), env}) {
    std::shared_ptr<const scene> s = load_scene(spec);
    ASSERT_TRUE(s->description().scene_camera) << spec << ": the case where the override was lost";
    render_params narrow = params;
    narrow.view.hfov_deg = 40;
    renderer wide_r(s, params), narrow_r(s, narrow);
    EXPECT_EQ(narrow_r.cam().hfov_deg, 40.0f) << spec;
    EXPECT_EQ(wide_r.cam().hfov_deg, s->description().scene_camera->hfov_deg) << spec;
    wide_r.use_pointset(set);
    narrow_r.use_pointset(set);
    const frame a = wide_r.foveated({32, 24}, params);
    EXPECT_GT(max_difference(a, narrow_r.foveated({32, 24}, narrow)), 0.02f) << spec;
  }
  render_params bad = params;
  bad.view.hfov_deg = 180;
  EXPECT_NE(validate(bad), "");
  EXPECT_THROW(renderer(scn, bad), usage_error);
}

// A camera path that turns the built-in scene's camera right by `deg_per_ms` degrees a
// millisecond about its eye, keyed every millisecond from 0 to 40 ms.
std::shared_ptr<const camera_path> turning_path(const camera& c, double deg_per_ms) {
  auto path = std::make_shared<camera_path>();
  const glm::vec3 right = glm::normalize(glm::cross(c.forward, c.up)), ahead = glm::normalize(c.forward);
  for (int t = 0; t <= 40; ++t) {
    const double a = glm::radians(deg_per_ms * t);
    const glm::vec3 target = c.position + float(std::cos(a)) * ahead + float(std::sin(a)) * right;
    path->keys.push_back({double(t), {c.position.x, c.position.y, c.position.z}, {target.x, target.y, target.z}});
  }
  return path;
}

TEST(Rolling, LinesAreShownInScanoutOrderAcrossThePeriod) {
  rolling_params r;
  r.frame_period_ms = 10;
  EXPECT_EQ(line_time_ms(r, 3, 40, 20), 0.0);  // global: at once
  r.order = scanout::top_down;
  EXPECT_DOUBLE_EQ(line_time_ms(r, 0, 40, 20), 0.25);
  EXPECT_DOUBLE_EQ(line_time_ms(r, 19, 40, 20), 9.75);
  r.order = scanout::bottom_up;
  EXPECT_DOUBLE_EQ(line_time_ms(r, 19, 40, 20), 0.25);
  EXPECT_DOUBLE_EQ(line_time_ms(r, 0, 40, 20), 9.75);
  r.order = scanout::left_right;
  EXPECT_DOUBLE_EQ(line_time_ms(r, 0, 40, 20), 0.125);
  EXPECT_DOUBLE_EQ(line_time_ms(r, 39, 40, 20), 9.875);
  r.order = scanout::right_left;
  EXPECT_DOUBLE_EQ(line_time_ms(r, 39, 40, 20), 0.125);
  // Each line's camera is the path's at start + its time.
  const camera base = look_at({0, 0, 0}, {0, 0, -1}, 60);
  const std::shared_ptr<const camera_path> path = sideways_path();
  r.path = path;
  r.start_ms = 105;
  for (scanout order : {scanout::top_down, scanout::bottom_up, scanout::left_right, scanout::right_left}) {
    r.order = order;
    const line_cameras l = rolling_cameras(r, base, 40, 20);
    const bool columns = order == scanout::left_right || order == scanout::right_left;
    EXPECT_EQ(l.columns, columns);
    ASSERT_EQ(l.cameras.size(), columns ? 40u : 20u);
    for (size_t i : {size_t(0), l.cameras.size() - 1})
      EXPECT_NEAR(l.cameras[i].position.x, 105 + line_time_ms(r, int(i), 40, 20) - 100, 1e-5) << scanout_name(order);
  }
  r.order = scanout::global;
  EXPECT_TRUE(rolling_cameras(r, base, 40, 20).empty());
  // Out of range: one line naming the flag.
  rolling_params bad;
  bad.frame_period_ms = 0.5;
  EXPECT_NE(validate(bad).find("--frame-period"), std::string::npos);
  bad = {};
  bad.start_ms = std::nan("");
  EXPECT_NE(validate(bad).find("--camera-time"), std::string::npos);
  bad = {};
  bad.order = scanout::top_down;  // no path to move along
  EXPECT_NE(validate(bad).find("--rolling needs --camera"), std::string::npos);
  EXPECT_EQ(validate(r), "");
}

TEST_F(pipeline, RollingWithAStillCameraIsTheGlobalFrame) {
  render_params rolling = params;
  auto still = std::make_shared<camera_path>();  // one key: the camera stays
  const camera c = setup_camera(*scn);
  const glm::vec3 target = c.position + c.forward;
  still->keys = {{0, {c.position.x, c.position.y, c.position.z}, {target.x, target.y, target.z}}};
  rolling.rolling.path = still;
  renderer global_r(scn, rolling);
  global_r.use_pointset(set);
  const frame global = global_r.foveated({20, 30}, rolling);
  const frame global_full = global_r.reference(64, 48, rolling).image;
  EXPECT_LT(glm::distance(global_r.cam().forward, c.forward), 1e-6f);  // the scene's view
  for (scanout order : {scanout::top_down, scanout::right_left}) {
    rolling.rolling.order = order;
    renderer r(scn, rolling);
    r.use_pointset(set);
    EXPECT_EQ(max_difference(r.foveated({20, 30}, rolling), global), 0.0f) << scanout_name(order);
    EXPECT_EQ(max_difference(r.reference(64, 48, rolling).image, global_full), 0.0f) << scanout_name(order);
  }
}

TEST_F(pipeline, ARollingFrameShowsEachRowAsTheCameraSeesItThen) {
  render_params rolling = params;
  rolling.rolling.path = turning_path(setup_camera(*scn), 0.5);
  rolling.rolling.order = scanout::top_down;
  rolling.rolling.frame_period_ms = 16;
  rolling.rolling.start_ms = 4;
  renderer r(scn, rolling);
  // The renderer's camera is the path's when the scanout begins.
  EXPECT_EQ(r.cam().forward, rolling.rolling.path->at(4, setup_camera(*scn)).forward);
  const frame f = r.reference(64, 48, rolling).image;
  render_params at_start = rolling;
  at_start.rolling.order = scanout::global;
  const frame global = renderer(scn, at_start).reference(64, 48, at_start).image;
  int rows_moved = 0;
  for (int y : {0, 20, 47}) {
    // Row y is the row of a global frame at the time it is shown.
    render_params then = at_start;
    then.rolling.start_ms = 4 + line_time_ms(rolling.rolling, y, 64, 48);
    const frame g = renderer(scn, then).reference(64, 48, then).image;
    bool moved = false;
    for (int x = 0; x < 64; ++x) {
      const size_t i = size_t(y) * 64 + x;
      EXPECT_EQ(f.rgb[i], g.rgb[i]) << x << "," << y;
      moved |= f.rgb[i] != global.rgb[i];
    }
    rows_moved += moved;
  }
  EXPECT_GE(rows_moved, 2);  // the later rows differ from the frame at the scanout's start
}

TEST_F(pipeline, RayPatternsFollowTheFrameNumberUnderTaaOnly) {
  render_params p = params;
  p.seed = 10;
  for (uint64_t n : {0, 1, 2, 3, 7}) {
    EXPECT_EQ(renderer::frame_trace_params(p, n).seed, 10u) << "without TAA nothing integrates new positions";
    p.taa = true;
    p.pattern = ray_pattern::reseed;
    EXPECT_EQ(renderer::frame_trace_params(p, n).seed, 10 + n);
    p.pattern = ray_pattern::mirror;
    EXPECT_EQ(renderer::frame_trace_params(p, n).mirror_x, (n & 1) != 0);
    EXPECT_EQ(renderer::frame_trace_params(p, n).mirror_y, (n & 2) != 0);
    EXPECT_EQ(renderer::frame_trace_params(p, n).seed, 10u);
    p.pattern = ray_pattern::fixed;
    EXPECT_EQ(renderer::frame_trace_params(p, n).seed, 10u);
    EXPECT_FALSE(renderer::frame_trace_params(p, n).mirror_x);
    p.taa = false;
  }
  // A warm-up moves neither the pattern nor the history.
  renderer r(scn, params);
  r.use_pointset(set);
  r.warm_up({32, 24}, params);
  EXPECT_EQ(r.frames_traced(), 0u);
}

TEST_F(pipeline, TaaFramesMatchTheLibraryPairFrameByFrame) {
  render_params p = params;
  p.taa = true;
  p.pattern = ray_pattern::reseed;
  renderer r(scn, p);
  r.use_pointset(set);
  taa_state state;
  const camera cam = setup_camera(*scn);
  const gaze_point g{30, 20};
  for (uint64_t n = 0; n < 3; ++n) {
    frame_timing t;
    const frame got = r.foveated(g, p, &t);
    const points_trace traced = trace_points(*scn, cam, *set, g, renderer::frame_trace_params(p, n));
    const frame expected = taa_resolve(state, reconstruct(*set, traced.samples, p.reconstruct), cam, set->model.display, g);
    EXPECT_LT(max_difference(got, expected), 1e-6f) << "frame " << n;
    EXPECT_GT(t.taa_ms, 0.0);
  }
}

TEST_F(pipeline, SteadyStateIsTheTaaSequenceFromFrameZeroWhateverCameBefore) {
  const gaze_point g{30, 20};
  for (ray_pattern pattern : {ray_pattern::reseed, ray_pattern::mirror}) {
    render_params p = params;
    p.pattern = pattern;
    // The sequence by hand: frame n traced in pattern n, blended from an empty history.
    render_params taa = p;
    taa.taa = true;
    renderer fresh(scn, taa);
    fresh.use_pointset(set);
    frame by_hand;
    for (int n = 0; n < 5; ++n) by_hand = fresh.foveated(g, taa);
    // steady_state on a renderer that traced and blended other frames before.
    renderer used(scn, p);
    used.use_pointset(set);
    for (int n = 0; n < 3; ++n) used.foveated({10, 10}, taa);
    const frame got = used.steady_state(g, p, 5);
    EXPECT_EQ(max_difference(got, by_hand), 0.0f) << label_of(ray_pattern_labels, pattern);
    // One frame passes through TAA: the single frame, bit for bit.
    renderer single(scn, p);
    single.use_pointset(set);
    EXPECT_EQ(max_difference(used.steady_state(g, p, 1), single.foveated(g, p)), 0.0f) << label_of(ray_pattern_labels, pattern);
    EXPECT_GT(max_difference(got, single.foveated(g, p)), 0.01f) << "five frames blended are one frame";
  }
}

TEST_F(pipeline, FullGridSteadyStateBlendsTheFramesOfEachPattern) {
  const display_geometry d = set->model.display;
  const gaze_point g{30, 20};
  renderer r(scn, params);
  const camera cam = setup_camera(*scn);
  // One frame: the full-resolution frame (and the falloff frame) itself.
  EXPECT_EQ(max_difference(r.full_steady_state(d, g, params, 1), r.reference(d.width, d.height, params).image), 0.0f);
  ray_falloff f;
  f.model.display = d, f.gaze = g, f.floor = 1;
  EXPECT_EQ(max_difference(r.full_steady_state(d, g, params, 1, &f), r.falloff_frame(f, params).image), 0.0f);
  // Several: taa_resolve over frame n's pattern (reseed: seed + n; mirror: samples m spp ..).
  for (ray_pattern pattern : {ray_pattern::reseed, ray_pattern::mirror}) {
    render_params p = params;
    p.pattern = pattern;
    render_params taa = p;
    taa.taa = true;
    taa_state state;
    frame expected;
    for (uint64_t n = 0; n < 6; ++n)
      expected = taa_resolve(state, trace_reference(*scn, cam, d.width, d.height, renderer::frame_trace_params(taa, n)).image,
                             cam, d, g);
    const frame got = r.full_steady_state(d, g, p, 6);
    EXPECT_EQ(max_difference(got, expected), 0.0f) << label_of(ray_pattern_labels, pattern);
    // and it is closer to a converged frame than one frame is: the rays of several patterns.
    render_params converged = params;
    converged.spp = 256;
    converged.seed = converged_seeds(params.seed).first;
    const frame truth = r.reference(d.width, d.height, converged).image;
    const double one = mean_abs(r.reference(d.width, d.height, params).image, truth), blended = mean_abs(got, truth);
    EXPECT_LT(blended, 0.8 * one) << label_of(ray_pattern_labels, pattern) << ": " << blended << " vs one frame's " << one;
  }
}

TEST_F(pipeline, TracingAheadGivesTheSameFrame) {
  renderer in_turn(scn, params), ahead(scn, params);
  in_turn.use_pointset(set);
  ahead.use_pointset(set);
  for (const gaze_point g : {gaze_point{32, 24}, gaze_point{10, 40}, gaze_point{60, 5}}) {
    frame_timing t;
    ahead.begin_trace(g, ahead.cam(), params);
    const frame b = ahead.foveated(g, params, &t);
    EXPECT_TRUE(t.traced_ahead);
    const frame a = in_turn.foveated(g, params);
    EXPECT_EQ(max_difference(a, b), 0.0f) << "gaze " << g.x << ", " << g.y;
  }
}

TEST_F(pipeline, AStaleTraceIsDroppedNotShown) {
  renderer in_turn(scn, params), ahead(scn, params);
  in_turn.use_pointset(set);
  ahead.use_pointset(set);
  frame_timing t;
  // Traced ahead for another gaze: the frame must be the one for the gaze asked for.
  ahead.begin_trace({5, 5}, ahead.cam(), params);
  frame b = ahead.foveated({50, 30}, params, &t);
  EXPECT_FALSE(t.traced_ahead);
  EXPECT_EQ(max_difference(in_turn.foveated({50, 30}, params), b), 0.0f);
  // ... for another camera (the view moved after the trace began).
  camera moved = ahead.cam();
  moved.position += glm::vec3(0.5f, 0, 0);
  ahead.begin_trace({50, 30}, ahead.cam(), params);
  ahead.cam() = moved;
  in_turn.cam() = moved;
  b = ahead.foveated({50, 30}, params, &t);
  EXPECT_FALSE(t.traced_ahead);
  const frame a = in_turn.foveated({50, 30}, params);
  EXPECT_EQ(max_difference(a, b), 0.0f);
  // ... for other rays per point, and another k (another set of traced points).
  render_params more = params;
  more.spp = 3;
  ahead.begin_trace({50, 30}, ahead.cam(), params);
  b = ahead.foveated({50, 30}, more, &t);
  EXPECT_FALSE(t.traced_ahead);
  EXPECT_EQ(max_difference(in_turn.foveated({50, 30}, more), b), 0.0f);
  more = params;
  more.reconstruct.k = 8;
  ahead.begin_trace({50, 30}, ahead.cam(), params);
  b = ahead.foveated({50, 30}, more, &t);
  EXPECT_FALSE(t.traced_ahead);
  EXPECT_EQ(max_difference(in_turn.foveated({50, 30}, more), b), 0.0f);
  // The frames differ at all between these cases (else the checks above prove nothing).
  const frame near_corner = in_turn.foveated({5, 5}, params);  // a copy: foveated() reuses its frame
  EXPECT_GT(max_difference(near_corner, in_turn.foveated({50, 30}, params)), 0.01f);
}

TEST_F(pipeline, WithoutTaaTheRayPatternStaysFixed) {
  renderer r(scn, params);
  r.use_pointset(set);
  const frame a = r.foveated({32, 24}, params);
  const frame b = r.foveated({32, 24}, params);
  EXPECT_EQ(max_difference(a, b), 0.0f);
  EXPECT_GT(max_difference(a, r.foveated({40, 20}, params)), 0.01f);  // and the comparison can fail
}

TEST_F(pipeline, FlickerFallsWithTaaAndTheViewIsRestored) {
  renderer r(scn, params);
  r.use_pointset(set);
  const camera before = r.cam();
  flicker_params f;
  f.frames = 6;
  const flicker_report fl = measure_flicker(r, {32, 24}, params, f);
  std::cout << "flicker raw " << fl.raw << ", TAA " << fl.taa << ", reference " << fl.reference << "\n";
  EXPECT_GT(fl.raw, 0.0);
  EXPECT_GT(fl.reference, 0.0);  // the camera turns: the reference itself changes
  EXPECT_LT(fl.taa, fl.raw);
  EXPECT_TRUE(same_view(r.cam(), before));
  f.frames = 1;
  EXPECT_THROW(measure_flicker(r, {32, 24}, params, f), std::invalid_argument);
}

// The video JOD along the path: against converged frames, the sequences score below 10 and
// below the converged path's own floor (a second seed against the first).
TEST_F(pipeline, VideoJodAlongThePathAgainstConvergedFrames) {
  renderer r(scn, params);
  r.use_pointset(set);
  const camera before = r.cam();
  flicker_params f;
  f.frames = 4;
  const auto [seed_a, seed_b] = converged_seeds(params.seed);
  const std::vector<frame> first = converged_path(r, params, 64, seed_a, f), second = converged_path(r, params, 64, seed_b, f);
  ASSERT_EQ(first.size(), 4u);
  EXPECT_TRUE(same_view(r.cam(), before));
  EXPECT_NE(first[0].rgb, first[3].rgb);  // the camera turned
  const fvvdp_result floor = converged_path_floor(second, first, {32, 24}, set->model.display, f);
  const flicker_report fl = measure_flicker(r, {32, 24}, params, f, first);
  ASSERT_TRUE(fl.has_jod);
  std::cout << "video JOD raw " << fl.jod_raw.jod << ", TAA " << fl.jod_taa.jod << ", full " << fl.jod_full.jod << ", floor "
            << floor.jod << "\n";
  EXPECT_EQ(fl.jod_raw.frames, 4);
  for (const fvvdp_result* j : {&fl.jod_raw, &fl.jod_taa, &fl.jod_full}) {
    EXPECT_LT(j->jod, 10.0);
    EXPECT_LT(j->jod, floor.jod);
  }
  EXPECT_FALSE(measure_flicker(r, {32, 24}, params, f).has_jod);
  EXPECT_THROW(measure_flicker(r, {32, 24}, params, f, std::vector<frame>(first.begin(), first.begin() + 3)),
               std::invalid_argument);
}

// The device path (OpenCL kernels, TAA kernel) gives the C++ path's frames within float
// rounding, for every method, with and without TAA; the timing says which path ran.
TEST_F(pipeline, TheDevicePathGivesTheCppFrames) {
  render_params on = params;
  on.device = reconstruct_device::opencl;
  renderer gpu(scn, on), cpu(scn, params);
  gpu.use_pointset(set);
  cpu.use_pointset(set);
  if (!gpu.on_device()) {
    if (opencl_required()) FAIL() << "no OpenCL device, and FOV_REQUIRE_OPENCL=1: " << gpu.device_problem();
    GTEST_SKIP() << "no OpenCL device: " << gpu.device_problem();
  }
  EXPECT_EQ(gpu.device_problem(), "");
  for (method m : {method::nn, method::shepard, method::rbf, method::barycentric, method::natural})
    for (bool taa : {false, true}) {
      on.reconstruct.how = m, on.taa = taa;
      render_params off = params;
      off.reconstruct.how = m, off.taa = taa;
      for (int n = 0; n < 3; ++n) {
        frame_timing tg, tc;
        const frame a = gpu.foveated({30, 20}, on, &tg);
        const frame b = cpu.foveated({30, 20}, off, &tc);
        EXPECT_TRUE(tg.on_device);
        EXPECT_FALSE(tc.on_device);
        float worst = 0, brightest = 0;  // float kernels against double C++: relative to the value
        for (size_t i = 0; i < a.rgb.size(); ++i)
          for (int c = 0; c < 3; ++c) {
            worst = std::max(worst, std::fabs(a.rgb[i][c] - b.rgb[i][c]) / std::max(1.0f, std::fabs(b.rgb[i][c])));
            brightest = std::max(brightest, b.rgb[i][c]);
          }
        EXPECT_LT(worst, 1e-4f) << method_name(m) << " taa " << taa << " frame " << n << " (brightest " << brightest << ")";
      }
    }
}

// Issue 15: where the set is a pixel grid, the foveated frame is the full-resolution frame
// with the same rays per pixel, bit for bit, whatever the method, gaze or device.
struct foveal_grid : ::testing::Test {
  std::shared_ptr<const scene> scn = load_scene("builtin");
  std::shared_ptr<pointset> set = [] {
    knn_params kp;
    kp.k = 8;
    auto s = std::make_shared<pointset>(generate_pointset(testing::partial_grid_model(), testing::grid_darts(), kp));
    set_knn_radii(s->table, s->points);
    return s;
  }();
  int w = set->model.display.width, h = set->model.display.height;
  // Calls f(screen index, canvas pixel is a grid pixel) for every screen pixel.
  template <class F>
  void each_pixel(gaze_point g, F&& f) const {
    const canvas_offset o = offset_for_gaze(set->model.display, g);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        f(size_t(y) * w + x, is_grid_pixel(set->model, set->darts, uint32_t(x + o.x), uint32_t(y + o.y)));
  }
};

TEST_F(foveal_grid, GridPixelsAreTheFullResolutionFrameExactly) {
  render_params p;
  p.taa = false;
  p.reconstruct.k = 5;
  for (reconstruct_device device : {reconstruct_device::cpp, reconstruct_device::opencl})
    for (uint32_t spp : {1u, 4u})
      for (method m : {method::nn, method::shepard, method::rbf, method::barycentric, method::natural})
        for (gaze_point g : {screen_centre(set->model.display), gaze_point{30, 70}}) {
          p.spp = spp, p.reconstruct.how = m, p.device = device;
          renderer r(scn, p);
          r.use_pointset(set);
          if (device == reconstruct_device::opencl && !r.on_device()) {
            if (opencl_required()) FAIL() << "no OpenCL device, and FOV_REQUIRE_OPENCL=1: " << r.device_problem();
            continue;
          }
          const frame fov = r.foveated(g, p);
          const frame full = r.reference(w, h, p).image;
          size_t grid = 0, same = 0, other_differ = 0;
          each_pixel(g, [&](size_t i, bool on_grid) {
            if (!on_grid) {
              other_differ += fov.rgb[i] != full.rgb[i];
              return;
            }
            ++grid;
            same += fov.rgb[i] == full.rgb[i] && fov.depth[i] == full.depth[i];
          });
          const std::string what = fmt::format("{} {} spp {} gaze {},{}", label_of(reconstruct_device_labels, device), spp,
                                               method_name(m), g.x, g.y);
          EXPECT_GT(grid, 2000u) << what;
          EXPECT_EQ(same, grid) << what;
          EXPECT_GT(other_differ, (size_t(w * h) - grid) / 10) << what << ": outside the grid the set is sparser";
        }
}

// A camera sliding sideways over the built-in scene, 2 rays per pixel a frame. Against a
// 16-ray rendering of the same camera, the TAA output must be no farther than the raw
// frame is (no ghost trail), and reprojecting must beat reading the history in place.
TEST(Taa, AMovingCameraLeavesNoGhostTrail) {
  const auto s = load_scene("builtin");
  trace_params fast, converged;
  fast.spp = 2;
  // Independent positions: the noise TAA integrates away (stratified 2-spp frames have
  // little left for it, while its reprojection still resamples).
  fast.sampler = pixel_sampler::random;
  converged.spp = 16;
  converged.seed = 99;
  const display_geometry d{96, 108, 1.0};
  const gaze_point gaze{48, 54};
  taa_state with, without;
  double raw = 0, ghost_with = 0, ghost_without = 0;
  const int frames = 12;
  for (int n = 0; n < frames; ++n) {
    camera cam = s->default_camera();
    cam.position.x += 0.08f * float(n);  // 8 cm a frame: about 1.5 px at 10 m
    fast.seed = uint64_t(n + 1);          // new ray positions every frame, as TAA expects
    const frame now = trace_reference(*s, cam, d.width, d.height, fast).image;
    const frame truth = trace_reference(*s, cam, d.width, d.height, converged).image;
    const frame a = taa_resolve(with, now, cam, d, gaze);
    without.cam = cam;  // pretend nothing moved: the history is read in place
    const frame b = taa_resolve(without, now, cam, d, gaze);
    if (n < 4) continue;
    raw += mean_abs(now, truth), ghost_with += mean_abs(a, truth), ghost_without += mean_abs(b, truth);
  }
  std::cout << "mean |x - 16 spp| over frames 4..11: raw frame " << raw / 8 << ", TAA reprojected "
            << ghost_with / 8 << ", TAA not reprojected " << ghost_without / 8 << "\n";
  EXPECT_LT(ghost_with, raw) << "TAA must not be farther from the converged image than the raw frame";
  EXPECT_LT(ghost_with, 0.8 * ghost_without);
}

TEST(Timing, MediansAndPairedSpeedups) {
  EXPECT_EQ(summarise({3, 1, 2}).median, 2);
  EXPECT_EQ(summarise({4, 1, 3, 2}).median, 2.5);  // even count: the middle two's mean
  const paired_timing t = pair_timings({10, 20, 10}, {40, 40, 50});
  EXPECT_EQ(t.frame_ms.median, 10);
  EXPECT_EQ(t.full_ms.median, 40);
  EXPECT_EQ(t.speedup.median, 4);  // per repetition: 4, 2, 5
  EXPECT_EQ(t.speedup.min, 2);
  EXPECT_EQ(t.speedup.max, 5);
  EXPECT_THROW(pair_timings({1, 2}, {1}), std::invalid_argument);
}

// The paired measurement's shape (not its speed): one foveated and one full frame per
// repetition, summaries ordered, the image the renderer's.
TEST(Timing, MeasureSpeedupPairsEveryRepetition) {
  std::shared_ptr<const scene> s = load_scene("builtin");
  render_params p;
  p.spp = 1;
  p.device = reconstruct_device::cpp;
  renderer r(s, p);
  std::shared_ptr<const pointset> set = small_set(48, 40);
  r.use_pointset(set);
  const uint64_t before = r.frames_traced();
  const paired_timing t = measure_speedup(r, {24, 20}, p, 48, 40, 3);
  EXPECT_EQ(r.frames_traced(), before + 3);
  for (const timing& x : {t.frame_ms, t.full_ms, t.speedup}) {
    EXPECT_GT(x.min, 0);
    EXPECT_LE(x.min, x.median);
    EXPECT_LE(x.median, x.max);
  }
  EXPECT_THROW(measure_speedup(r, {24, 20}, p, 48, 40, 0), std::invalid_argument);
}

TEST(ConvergedSeeds, ShareNothingWithTheSweepsFrames) {
  for (uint64_t seed : {1ull, 2ull, 1000ull}) {
    const auto [a, b] = converged_seeds(seed);
    EXPECT_NE(a, b);
    for (uint64_t n = 0; n < 1000; ++n) EXPECT_TRUE(a != seed + n && b != seed + n);
  }
}

// Temporal reuse (fov/reuse.h).
TEST_F(pipeline, AStillViewKeepsItsPeripheralSamplesAndTheSameFrame) {
  uint64_t kept_points[2][2] = {};  // by edges and distance
  for (const reuse_edges edges : {reuse_edges::strict, reuse_edges::silhouettes})
    for (const reuse_distance distance : {reuse_distance::world, reuse_distance::screen}) {
      SCOPED_TRACE(fmt::format("{}, {}", label_of(reuse_edges_labels, edges), label_of(reuse_distance_labels, distance)));
      render_params reusing = params;
      reusing.reuse.mode = reuse_mode::temporal;
      reusing.reuse.fovea_deg = 3;
      reusing.reuse.edges = edges;
      reusing.reuse.distance = distance;
      renderer full(scn, params), r(scn, reusing);
      full.use_pointset(set);
      r.use_pointset(set);
      const gaze_point g{20, 30};
      frame_timing first, second;
      r.foveated(g, reusing, &first);
      EXPECT_TRUE(first.reused);
      EXPECT_EQ(first.reuse.reused, 0u);  // nothing to keep yet
      EXPECT_EQ(first.rays, first.reuse.rays_traced + first.reuse.probe_rays);
      const frame kept = r.foveated(g, reusing, &second);
      const frame traced = full.foveated(g, params);
      EXPECT_EQ(kept.rgb, traced.rgb);  // a kept sample is what the same rays would give again
      EXPECT_EQ(kept.depth, traced.depth);
      // Points outside 9 degrees keep their samples but near edges (on this 64 x 48 screen many
      // are); those within 3 degrees do not.
      EXPECT_GT(second.reuse.reused_share(), 0.4) << second.reuse.reused << " of " << second.reuse.points;
      EXPECT_EQ(second.reuse.points, second.reuse.reused + second.reuse.traced);
      uint64_t banded = 0, banded_kept = 0;
      for (size_t b = 0; b < reuse_bands; ++b) {
        banded += second.reuse.points_by_band[b], banded_kept += second.reuse.reused_by_band[b];
        EXPECT_LE(second.reuse.reused_by_band[b], second.reuse.points_by_band[b]);
      }
      EXPECT_EQ(banded, second.reuse.points);
      EXPECT_EQ(banded_kept, second.reuse.reused);
      uint64_t judged = 0;
      for (const uint64_t n : second.reuse.by_verdict) judged += n;
      EXPECT_EQ(judged, second.reuse.points);
      EXPECT_EQ(second.reuse.by_verdict[size_t(reuse_verdict::kept)], second.reuse.reused);
      EXPECT_EQ(first.reuse.by_verdict[size_t(reuse_verdict::no_history)], first.reuse.points);
      EXPECT_GT(second.reuse.by_verdict[size_t(reuse_verdict::eccentricity)], 0u);  // the fovea
      EXPECT_EQ(second.reuse.by_verdict[size_t(reuse_verdict::no_history)], 0u);
      EXPECT_EQ(second.points_traced, second.reuse.traced);
      EXPECT_EQ(second.rays, second.reuse.traced * params.spp + second.reuse.probe_rays);
      EXPECT_LT(second.rays, first.rays);
      spacing_model eye = set->model;
      eye.scale = 1;
      uint64_t central = 0;  // the gaze sits on the canvas centre (64, 48)
      for (uint32_t i : traced_points(*set, g, params.reconstruct.k))
        central += eccentricity_deg(eye, std::hypot(set->points[i].x - 64.0, set->points[i].y - 48.0)) < 3;
      EXPECT_GT(central, 0u);
      EXPECT_GE(second.reuse.traced, central);
      kept_points[size_t(edges)][size_t(distance)] = second.reuse.reused;
    }
  // With silhouettes only, the sloped discs (the far floor) keep theirs too; in a still view
  // both distances are nought for each point's own sample.
  for (size_t e = 0; e < 2; ++e) EXPECT_EQ(kept_points[e][0], kept_points[e][1]);
  EXPECT_GT(kept_points[size_t(reuse_edges::silhouettes)][0], kept_points[size_t(reuse_edges::strict)][0]);
}

TEST_F(pipeline, EverySampleIsTracedAgainWithinItsMaximumAge) {
  render_params reusing = params;
  reusing.reuse.mode = reuse_mode::temporal;
  reusing.reuse.fovea_deg = 0;  // everything may be kept
  reusing.reuse.max_age = 2;
  renderer r(scn, reusing);
  r.use_pointset(set);
  std::vector<uint64_t> kept;
  for (int n = 0; n < 5; ++n) {
    frame_timing t;
    r.foveated({32, 24}, reusing, &t);
    kept.push_back(t.reuse.reused);
  }
  // Traced at frame 0, kept at 1 and 2 (ages 1 and 2), all traced again at 3, kept at 4.
  EXPECT_EQ(kept[0], 0u);
  EXPECT_GT(kept[1], 0u);
  EXPECT_EQ(kept[2], kept[1]);
  EXPECT_EQ(kept[3], 0u);
  EXPECT_EQ(kept[4], kept[1]);
  // Settings that change the samples drop them.
  render_params brighter = reusing;
  brighter.exposure_ev = 1;
  frame_timing t;
  r.foveated({32, 24}, brighter, &t);
  EXPECT_EQ(t.reuse.reused, 0u);
}

// Two emitting quads, a red one in front of a blue wall (at z = -10), the red one placed at
// x0..x0 + 1 and depth z.
scene_description red_before_blue(float x0, float z = -5) {
  scene_description d;
  for (glm::vec3 c : {glm::vec3(0, 0, 1), glm::vec3(1, 0, 0)}) {
    material m;
    m.base_colour = glm::vec4(0, 0, 0, 1);
    m.emissive = c;
    d.materials.push_back(m);
  }
  auto quad = [&](float xa, float xb, float ya, float yb, float z, uint32_t mat) {
    mesh m;
    m.positions = {{xa, ya, z}, {xb, ya, z}, {xb, yb, z}, {xa, yb, z}};
    m.uvs.assign(4, glm::vec2(0.5f));
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.material = mat;
    d.meshes.push_back(m);
    d.instances.push_back({uint32_t(d.meshes.size() - 1), glm::mat4(1.0f), ""});
  };
  quad(-50, 50, -50, 50, -10, 0);
  quad(x0, x0 + 1, -1, 1, z, 1);
  d.lights.at(0).colour = glm::vec3(0);
  d.env.colour = glm::vec3(0);
  return d;
}

TEST(Reuse, AMovedObjectIsTracedWhereItWasAndWhereItIs) {
  const scene before(red_before_blue(-2)), after(red_before_blue(0.5f));
  const auto set = small_set(64, 48);
  const camera cam = look_at({0, 0, 0}, {0, 0, -1}, 90);
  trace_params tp;
  tp.spp = 4;
  tp.k = 5;
  const traced_index index = make_traced_index(*set, 5);
  for (const reuse_distance distance : {reuse_distance::world, reuse_distance::screen}) {
    SCOPED_TRACE(label_of(reuse_distance_labels, distance));
    reuse_params p;
    p.mode = reuse_mode::temporal;
    p.fovea_deg = 0;
    p.distance = distance;
    reuse_history history;
    const gaze_point g{32, 24};
    trace_reusing(before, cam, *set, index, g, tp, p, history);
    const reused_trace moved = trace_reusing(after, cam, *set, index, g, tp, p, history);
    const points_trace fresh = trace_points(after, cam, *set, index, g, tp);
    const point_probe now = probe_points(after, cam, *set, index, g, tp), then = probe_points(before, cam, *set, index, g, tp);
    ASSERT_EQ(now.points, moved.trace.samples.traced);
    ASSERT_GT(moved.report.reused, now.points.size() / 2);  // the wall, away from both places, is kept
    ASSERT_EQ(moved.kept.size(), moved.report.reused);
    uint64_t kept_wrong = 0, on_red = 0;
    for (size_t j = 0; j < now.points.size(); ++j) {
      const uint32_t i = now.points[j];
      const bool kept = std::binary_search(moved.kept.begin(), moved.kept.end(), i);
      if (now.distance[j] < 7 || then.distance[j] < 7) {  // its centre sees the red quad now or saw it
        ++on_red;
        EXPECT_FALSE(kept) << "point " << i << " kept a stale sample where the object moved";
      }
      if (kept) kept_wrong += moved.trace.samples.colour[i] != fresh.samples.colour[i];
    }
    EXPECT_GT(on_red, 20u);
    // Elsewhere a kept sample is the wall's colour, as a fresh trace gives, but for the rare disc
    // that reaches the moved quad without its centre or a neighbour seeing it.
    EXPECT_LE(kept_wrong, now.points.size() / 100) << kept_wrong << " of " << now.points.size();
  }
}

// Each frame writes its history over the arrays of the one before last (reuse_history::spare)
// instead of allocating them: along a moving camera with a short maximum age (so that ages
// matter), a history recycled frame after frame decides and keeps exactly what a fresh copy
// of it (a copy has no spare arrays) does.
TEST(Reuse, ARecycledHistoryDecidesAsAFreshOne) {
  const scene scn(red_before_blue(-2));
  const auto set = small_set(64, 48);
  trace_params tp;
  tp.spp = 4;
  tp.k = 5;
  const traced_index index = make_traced_index(*set, 5);
  reuse_params p;
  p.mode = reuse_mode::temporal;
  p.fovea_deg = 0;
  p.max_age = 2;
  reuse_history recycled, fresh;
  uint64_t kept = 0;
  for (uint32_t n = 0; n < 7; ++n) {
    const camera cam = look_at({0.01f * float(n), 0, 0}, {0.01f * float(n) + 0.02f * float(n), 0, -1}, 90);
    const gaze_point g{32.0 + n, 24};
    reuse_history copy = fresh;  // no spare arrays: this frame allocates
    const reused_trace a = trace_reusing(scn, cam, *set, index, g, tp, p, recycled);
    const reused_trace b = trace_reusing(scn, cam, *set, index, g, tp, p, copy);
    fresh = copy;
    ASSERT_EQ(a.kept, b.kept) << "frame " << n;
    ASSERT_EQ(a.trace.samples.colour, b.trace.samples.colour) << "frame " << n;
    ASSERT_EQ(recycled.kind, fresh.kind) << "frame " << n;
    // (Entries of points not seen this frame are stale in recycled arrays and never read.)
    for (size_t i = 0; i < fresh.kind.size(); ++i)
      if (fresh.kind[i] != reuse_history::seen::nothing) {
        ASSERT_EQ(recycled.age[i], fresh.age[i]) << "frame " << n;
      }
    if (n >= 2) {
      EXPECT_FALSE(recycled.spare.kind.empty()) << "frame " << n << " recycled nothing";
    }
    kept += a.report.reused;
  }
  EXPECT_GT(kept, 0u);
}

TEST_F(pipeline, AMovingCameraKeepsWhatStillHoldsAndTracesTheRest) {
  render_params reusing = params;
  reusing.reuse.mode = reuse_mode::temporal;
  reusing.reuse.fovea_deg = 3;
  render_params other_seed = params;
  other_seed.seed = 2;
  renderer full(scn, params), r(scn, reusing), again(scn, reusing);
  full.use_pointset(set), r.use_pointset(set), again.use_pointset(set);
  const camera start = r.cam();
  flicker_params slide;
  slide.yaw_deg_per_frame = 0.3f;
  slide.shift_per_frame = 0.05f;  // parallax: the wall behind the boxes comes into view
  for (uint32_t n = 0; n < 6; ++n) {
    full.cam() = r.cam() = again.cam() = path_camera(start, slide, n);
    frame_timing t, u;
    const frame a = r.foveated({32, 24}, reusing, &t);
    const frame b = again.foveated({32, 24}, reusing, &u);
    EXPECT_EQ(a.rgb, b.rgb);  // deterministic
    EXPECT_EQ(t.reuse.reused, u.reuse.reused);
    const frame traced = full.foveated({32, 24}, params), noise = full.foveated({32, 24}, other_seed);
    const double kept_error = mean_abs(a, traced), seed_difference = mean_abs(noise, traced);
    std::printf("frame %u: kept %.3f of the points, |reuse - full| %.4f, |full seed 2 - full| %.4f\n", n,
                t.reuse.reused_share(), kept_error, seed_difference);
    if (n == 0) continue;
    EXPECT_GT(t.reuse.reused, 0u) << "frame " << n;
    EXPECT_GT(t.reuse.traced, 0u) << "frame " << n;  // the fovea and what moved into view
    // What reuse changes is smaller than what another seed's rays change.
    EXPECT_LT(kept_error, seed_difference) << "frame " << n;
  }
}

// Along a turning and moving camera, `looser` keeps more samples than `tighter` and still
// changes the frame less than another seed's rays do.
void looser_keeps_more(const pipeline& f, const render_params& tighter, const render_params& looser) {
  render_params other_seed = f.params;
  other_seed.seed = 2;
  renderer full(f.scn, f.params), a(f.scn, tighter), b(f.scn, looser);
  full.use_pointset(f.set), a.use_pointset(f.set), b.use_pointset(f.set);
  const camera start = a.cam();
  flicker_params slide;
  slide.yaw_deg_per_frame = 0.3f;
  slide.shift_per_frame = 0.05f;
  uint64_t kept_tighter = 0, kept_looser = 0;
  for (uint32_t n = 0; n < 4; ++n) {
    full.cam() = a.cam() = b.cam() = path_camera(start, slide, n);
    frame_timing ta, tb;
    a.foveated({32, 24}, tighter, &ta);
    const frame kept = b.foveated({32, 24}, looser, &tb);
    const frame traced = full.foveated({32, 24}, f.params), noise = full.foveated({32, 24}, other_seed);
    if (n == 0) continue;
    kept_tighter += ta.reuse.reused, kept_looser += tb.reuse.reused;
    EXPECT_LT(mean_abs(kept, traced), mean_abs(noise, traced)) << "frame " << n;
  }
  EXPECT_GT(kept_looser, kept_tighter);
}

// measure_reuse times the path with full and reusing traces (and full-resolution frames) in
// turn on one renderer: a full trace or a full-resolution frame between two reusing ones
// leaves what they keep as it was.
TEST_F(pipeline, AFullTraceBetweenReusingFramesLeavesTheReuseAsItWas) {
  render_params reusing = params, full = params;
  reusing.reuse.mode = reuse_mode::temporal;
  reusing.reuse.fovea_deg = 3;
  renderer a(scn, reusing), b(scn, reusing);
  a.use_pointset(set), b.use_pointset(set);
  const camera start = a.cam();
  flicker_params slide;
  slide.yaw_deg_per_frame = 0.3f;
  slide.shift_per_frame = 0.05f;
  for (uint32_t n = 0; n < 4; ++n) {
    a.cam() = b.cam() = path_camera(start, slide, n);
    frame_timing between, ta, tb;
    a.trace({32, 24}, full, between);
    a.reference(set->model.display.width, set->model.display.height, full);
    const points_trace pa = a.trace({32, 24}, reusing, ta), pb = b.trace({32, 24}, reusing, tb);
    EXPECT_EQ(ta.reuse.reused, tb.reuse.reused) << "frame " << n;
    EXPECT_EQ(ta.rays, tb.rays) << "frame " << n;
    EXPECT_EQ(pa.samples.colour, pb.samples.colour) << "frame " << n;
    if (n > 0) {
      EXPECT_GT(ta.reuse.reused, 0u);
    }
  }
  slide.frames = 3;
  const reuse_path_report rp = measure_reuse(a, {32, 24}, reusing, slide, {}, 2);
  EXPECT_EQ(rp.trace_ms_full.size(), 2u * 2u);  // two passes of frames 1 and 2
  ASSERT_EQ(rp.trace_ms_reuse.size(), rp.trace_ms_full.size());
  for (size_t i = 0; i < rp.trace_ms_full.size(); ++i) {
    EXPECT_GT(rp.trace_ms_full[i], 0.0);
    EXPECT_GT(rp.trace_ms_reuse[i], 0.0);
  }
  EXPECT_TRUE(rp.trace_ms_full_resolution.empty());
  const reuse_path_report with_full = measure_reuse(a, {32, 24}, reusing, slide, {}, 3, true);
  ASSERT_EQ(with_full.trace_ms_full_resolution.size(), 3u * 2u);  // three passes (each order once) of frames 1 and 2
  EXPECT_EQ(with_full.trace_ms_reuse.size(), 3u * 2u);
  for (double ms : with_full.trace_ms_full_resolution) EXPECT_GT(ms, 0.0);
  EXPECT_EQ(with_full.rays_reuse, rp.rays_reuse);
}

TEST_F(pipeline, SilhouetteEdgesKeepMoreAndStillChangeLessThanAnotherSeed) {
  render_params strict = params;
  strict.reuse.mode = reuse_mode::temporal;
  strict.reuse.fovea_deg = 3;
  render_params silhouettes = strict;
  silhouettes.reuse.edges = reuse_edges::silhouettes;
  looser_keeps_more(*this, strict, silhouettes);
}

// The far floor, seen at a grazing angle, spreads its samples in the world beyond a disc facing
// the camera; on the screen they lie within the points' spacing.
TEST_F(pipeline, ScreenDistanceKeepsMoreAndStillChangesLessThanAnotherSeed) {
  render_params world = params;
  world.reuse.mode = reuse_mode::temporal;
  world.reuse.fovea_deg = 3;
  world.reuse.edges = reuse_edges::silhouettes;
  render_params screen = world;
  screen.reuse.distance = reuse_distance::screen;
  looser_keeps_more(*this, world, screen);
}

TEST_F(pipeline, AReuseBudgetIsHonouredAndKeepsTheMostConfidentSamples) {
  render_params unlimited = params, large = params, tight = params;
  unlimited.reuse.mode = large.reuse.mode = tight.reuse.mode = reuse_mode::temporal;
  unlimited.reuse.fovea_deg = large.reuse.fovea_deg = tight.reuse.fovea_deg = 3;
  large.reuse.budget = max_reuse_budget;
  tight.reuse.budget = 7500;  // between what must be traced (edges, disocclusion) and what the threshold traces
  renderer a(scn, unlimited), b(scn, large), c(scn, tight);
  a.use_pointset(set), b.use_pointset(set), c.use_pointset(set);
  const camera start = a.cam();
  flicker_params slide;
  slide.yaw_deg_per_frame = 0.3f;
  slide.shift_per_frame = 0.05f;
  bool kept_for_budget = false;
  for (uint32_t n = 0; n < 4; ++n) {
    a.cam() = b.cam() = c.cam() = path_camera(start, slide, n);
    frame_timing ta, tb, tc;
    const frame fa = a.foveated({32, 24}, unlimited, &ta);
    const frame fb = b.foveated({32, 24}, large, &tb);
    c.foveated({32, 24}, tight, &tc);
    // A budget never reached changes nothing.
    EXPECT_EQ(fa.rgb, fb.rgb) << "frame " << n;
    EXPECT_EQ(tb.reuse.kept_for_budget, 0u);
    EXPECT_FALSE(tb.reuse.budget_short);
    std::printf("frame %u: unlimited traces %llu rays; budget 7500: %llu rays, %llu kept for it%s\n", n,
                (unsigned long long)ta.reuse.rays_traced, (unsigned long long)tc.reuse.rays_traced,
                (unsigned long long)tc.reuse.kept_for_budget, tc.reuse.budget_short ? " (short)" : "");
    EXPECT_EQ(tc.reuse.points, tc.reuse.reused + tc.reuse.traced);
    if (n == 0) {  // nothing to keep: every point is traced whatever the budget
      EXPECT_TRUE(tc.reuse.budget_short);
      EXPECT_EQ(tc.reuse.traced, tc.reuse.points);
      continue;
    }
    if (!tc.reuse.budget_short) {
      EXPECT_LE(tc.reuse.rays_traced, tight.reuse.budget) << "frame " << n;
      kept_for_budget |= tc.reuse.kept_for_budget > 0;
    }
    EXPECT_GE(tc.reuse.reused, ta.reuse.reused);
    EXPECT_LE(tc.reuse.rays_traced, ta.reuse.rays_traced);
  }
  EXPECT_TRUE(kept_for_budget);  // a frame within the budget that kept samples for it
}

TEST(Reuse, SettingsOutOfRangeAreRefusedNamingTheFlag) {
  reuse_params p;
  EXPECT_EQ(validate(p), "");
  p.fovea_deg = -1;
  EXPECT_NE(validate(p).find("--reuse-fovea"), std::string::npos);
  p = {};
  p.threshold = 1.5;
  EXPECT_NE(validate(p).find("--reuse-threshold"), std::string::npos);
  p = {};
  p.max_age = 0;
  EXPECT_NE(validate(p).find("--reuse-max-age"), std::string::npos);
  p = {};
  p.budget = max_reuse_budget + 1;
  EXPECT_NE(validate(p).find("--reuse-budget"), std::string::npos);
  render_params r;
  r.reuse.mode = reuse_mode::temporal;
  r.ray_floor = 1;
  EXPECT_NE(validate(r).find("--ray-floor"), std::string::npos);
  r.ray_floor = 0;
  r.adaptive.enabled = true;
  EXPECT_NE(validate(r).find("--adaptive"), std::string::npos);
}

// Two eyes (fov/stereo.h, fov/stereo_renderer.h).
bool same_frame(const frame& a, const frame& b) {
  return a.width == b.width && a.height == b.height && a.rgb == b.rgb && a.depth == b.depth;
}

TEST(Stereo, EyesSitHalfTheIpdToEitherSideLookingTheSameWay) {
  const camera head = look_at({1, 2, 3}, {1, 2, -7}, 70);
  const camera l = eye_camera(head, eye_side::left, 63), r = eye_camera(head, eye_side::right, 63);
  EXPECT_NEAR(glm::distance(l.position, r.position), 0.063f, 1e-6f);
  EXPECT_NEAR(l.position.x, 1 - 0.0315f, 1e-6f);  // looking down -z, the right is +x
  EXPECT_NEAR(r.position.x, 1 + 0.0315f, 1e-6f);
  EXPECT_NEAR(glm::distance(0.5f * (l.position + r.position), head.position), 0.0f, 1e-6f);
  for (const camera& c : {l, r}) {
    EXPECT_EQ(c.forward, head.forward);
    EXPECT_EQ(c.up, head.up);
    EXPECT_EQ(c.hfov_deg, head.hfov_deg);
  }
  EXPECT_TRUE(same_view(eye_camera(head, eye_side::right, 0), head));
  stereo_params p;
  EXPECT_EQ(validate(p), "");
  for (double bad : {-1.0, 1000.5, std::nan("")}) {
    p.ipd_mm = bad;
    EXPECT_NE(validate(p).find("--ipd must lie in 0..1000 mm"), std::string::npos) << bad;
  }
  render_params rp;
  rp.reuse.mode = reuse_mode::eyes;
  EXPECT_NE(validate(rp).find("--reuse eyes needs --stereo"), std::string::npos);
  rp.stereo.enabled = true;
  EXPECT_EQ(validate(rp), "");
  rp.ray_floor = 1;
  EXPECT_NE(validate(rp).find("--reuse eyes traces every point"), std::string::npos);
  rp = {};
  rp.stereo.enabled = true;
  rp.rolling.order = scanout::top_down;
  auto path = std::make_shared<camera_path>();
  path->keys.push_back({0, {0, 0, 0}, {0, 0, -1}});
  rp.rolling.path = path;
  EXPECT_EQ(validate(rp), "");  // two eyes on a rolling panel
  rp.reuse.mode = reuse_mode::eyes;
  EXPECT_NE(validate(rp).find("does not combine with --rolling"), std::string::npos);
}

// Two eyes on one rolling panel (the FOVE 0's: the eyes side by side): a row scanout shows
// both eyes' row at once, a column scanout the left eye's columns first; each line's camera
// is the eye's at the line's time.
TEST(Rolling, APanelOfTwoEyesScansThemAsOne) {
  rolling_params r;
  r.frame_period_ms = 10;
  r.stereo = true;
  for (bool right : {false, true}) {
    r.right_eye = right;
    r.order = scanout::top_down;  // an eye's row at the panel row's time
    EXPECT_DOUBLE_EQ(line_time_ms(r, 0, 40, 20), 0.25);
    EXPECT_DOUBLE_EQ(line_time_ms(r, 19, 40, 20), 9.75);
  }
  r.order = scanout::left_right;  // 80 columns across the panel
  r.right_eye = false;
  EXPECT_DOUBLE_EQ(line_time_ms(r, 0, 40, 20), 0.0625);
  EXPECT_DOUBLE_EQ(line_time_ms(r, 39, 40, 20), 4.9375);
  r.right_eye = true;
  EXPECT_DOUBLE_EQ(line_time_ms(r, 0, 40, 20), 5.0625);
  EXPECT_DOUBLE_EQ(line_time_ms(r, 39, 40, 20), 9.9375);
  r.order = scanout::right_left;  // the right eye's last column first
  EXPECT_DOUBLE_EQ(line_time_ms(r, 39, 40, 20), 0.0625);
  r.right_eye = false;
  EXPECT_DOUBLE_EQ(line_time_ms(r, 0, 40, 20), 9.9375);
  // Each line's camera: the eye's, of the path's head camera at the line's time.
  const camera base = look_at({0, 0, 0}, {0, 0, -1}, 60);
  const std::shared_ptr<const camera_path> path = sideways_path();
  r.path = path;
  r.start_ms = 105;
  r.ipd_mm = 500;  // eyes 0.25 to either side of the head
  for (scanout order : {scanout::top_down, scanout::left_right}) {
    r.order = order;
    for (bool right : {false, true}) {
      r.right_eye = right;
      const line_cameras l = rolling_cameras(r, base, 40, 20);
      for (size_t i : {size_t(0), l.cameras.size() - 1}) {
        const camera head = path->at(105 + line_time_ms(r, int(i), 40, 20), base);
        const camera want = eye_camera(head, right ? eye_side::right : eye_side::left, 500);
        EXPECT_EQ(l.cameras[i].position, want.position) << scanout_name(order) << " " << right << " " << i;
        EXPECT_NEAR(l.cameras[i].position.x, head.position.x + (right ? 0.25f : -0.25f), 1e-5);
        EXPECT_EQ(l.cameras[i].forward, want.forward);
      }
    }
  }
}

// At zero IPD both eyes sit at the head: on a column scanout each eye's frame is a one-eye
// rolling frame over its half of the period (the right eye's starting half a period later),
// and on a row scanout the one-eye rolling frame itself, bit for bit, foveated and at full
// resolution. A still path gives the global pair.
TEST_F(pipeline, TwoEyesOnARollingPanelAreOneEyeFramesOverTheirHalves) {
  render_params p = params;
  p.stereo.enabled = true;
  p.stereo.ipd_mm = 0;
  p.rolling.path = turning_path(setup_camera(*scn), 0.5);
  p.rolling.frame_period_ms = 16;
  p.rolling.start_ms = 4;
  for (scanout order : {scanout::left_right, scanout::top_down}) {
    p.rolling.order = order;
    stereo_renderer two(scn, p);
    two.use_pointset(set);
    const frame both = two.foveated({20, 30}, {40, 20}, p);
    const frame both_full = two.reference(64, 48, p);
    render_params one_p = p;
    one_p.stereo.enabled = false;
    const bool halves = order == scanout::left_right;
    if (halves) one_p.rolling.frame_period_ms = 8;
    renderer left(scn, one_p);
    left.use_pointset(set);
    EXPECT_TRUE(same_frame(eye_half(both, eye_side::left), left.foveated({20, 30}, one_p))) << scanout_name(order);
    EXPECT_TRUE(same_frame(eye_half(both_full, eye_side::left), left.reference(64, 48, one_p).image)) << scanout_name(order);
    if (halves) one_p.rolling.start_ms = 12;
    renderer right(scn, one_p);
    right.use_pointset(set);
    EXPECT_TRUE(same_frame(eye_half(both, eye_side::right), right.foveated({40, 20}, one_p))) << scanout_name(order);
    EXPECT_TRUE(same_frame(eye_half(both_full, eye_side::right), right.reference(64, 48, one_p).image)) << scanout_name(order);
    if (halves) {
      EXPECT_FALSE(same_frame(eye_half(both_full, eye_side::left), eye_half(both_full, eye_side::right)));
    }
  }
  // A still path: the rolling pair is the global pair.
  auto still = std::make_shared<camera_path>();
  const camera c = setup_camera(*scn);
  const glm::vec3 target = c.position + c.forward;
  still->keys = {{0, {c.position.x, c.position.y, c.position.z}, {target.x, target.y, target.z}}};
  p.rolling.path = still;
  p.stereo.ipd_mm = 63;
  render_params global = p;
  global.rolling.order = scanout::global;
  stereo_renderer g(scn, global);
  g.use_pointset(set);
  const frame want = g.foveated({20, 30}, {40, 20}, global);
  for (scanout order : {scanout::left_right, scanout::bottom_up}) {
    p.rolling.order = order;
    stereo_renderer r(scn, p);
    r.use_pointset(set);
    EXPECT_TRUE(same_frame(r.foveated({20, 30}, {40, 20}, p), want)) << scanout_name(order);
  }
}

TEST_F(pipeline, AtZeroIpdEachEyeIsTheHeadsFrame) {
  render_params p = params;
  p.stereo.enabled = true;
  p.stereo.ipd_mm = 0;
  stereo_renderer two(scn, p);
  renderer one(scn, p);
  two.use_pointset(set), one.use_pointset(set);
  stereo_timing t;
  const frame both = two.foveated({20, 30}, {40, 20}, p, &t);
  ASSERT_EQ(both.width, 128);
  ASSERT_EQ(both.height, 48);
  const frame l = one.foveated({20, 30}, p), r = one.foveated({40, 20}, p);
  EXPECT_TRUE(same_frame(both, side_by_side(l, r)));
  EXPECT_TRUE(same_frame(eye_half(both, eye_side::left), l));
  EXPECT_TRUE(same_frame(eye_half(both, eye_side::right), r));
  EXPECT_EQ(t.left.rays, t.left.points_traced * p.spp);
  EXPECT_EQ(t.right.rays, t.right.points_traced * p.spp);
  EXPECT_FALSE(t.left.reused || t.right.reused);
  // The full-resolution pair too.
  EXPECT_TRUE(same_frame(two.reference(64, 48, p), side_by_side(one.reference(64, 48, p).image, one.reference(64, 48, p).image)));
}

TEST_F(pipeline, TheEyesImagesOfASceneAtInfinityMatch) {
  const std::shared_ptr<const scene> env = load_scene(ramp_envmap());
  render_params p = params;
  p.stereo.enabled = true;
  p.stereo.ipd_mm = 63;
  p.taa = true;  // two frames, each eye's history and ray pattern advancing in step
  stereo_renderer two(env, p);
  two.use_pointset(set);
  render_params reusing = p;
  reusing.reuse.mode = reuse_mode::eyes;
  reusing.reuse.fovea_deg = 0;
  reusing.reuse.threshold = 0;
  stereo_renderer shared(env, reusing);
  shared.use_pointset(set);
  for (int n = 0; n < 2; ++n) {
    const frame both = two.foveated({30, 20}, {30, 20}, p);
    stereo_timing t;
    const frame kept = shared.foveated({30, 20}, {30, 20}, reusing, &t);
    const size_t half = 64;
    size_t differing = 0;
    for (int y = 0; y < both.height; ++y)
      for (size_t x = 0; x < half; ++x)
        differing += both.rgb[size_t(y) * 128 + x] != both.rgb[size_t(y) * 128 + half + x];
    EXPECT_EQ(differing, 0u) << "frame " << n;  // every direction is the same for both eyes
    EXPECT_TRUE(same_frame(kept, both)) << "frame " << n;  // the right eye keeps what it would trace
    // Every point the right eye needs keeps the left eye's sample: its only rays are the probes.
    EXPECT_TRUE(t.right.reused);
    EXPECT_EQ(t.right.reuse.reused, t.right.reuse.points);
    EXPECT_EQ(t.right.rays, t.right.reuse.probe_rays);
    EXPECT_EQ(t.right.reuse.rays_reused, t.left.rays);
  }
}

// A red quad 2 m away before a blue wall 10 m away, seen by two eyes a metre apart: each eye
// sees a strip of wall the other eye's view of the quad hides; the left eye traced.
struct eyes_apart : ::testing::Test {
  const scene s{red_before_blue(-0.5f, -2)};
  const std::shared_ptr<const pointset> set = small_set(64, 48);
  const camera head = look_at({0, 0, 0}, {0, 0, -1}, 90);
  const camera left = eye_camera(head, eye_side::left, 1000), right = eye_camera(head, eye_side::right, 1000);
  const gaze_point g{32, 24};
  trace_params tp;
  reuse_params p;
  std::unique_ptr<traced_index> index;
  points_trace seen;
  void SetUp() override {
    tp.spp = 4;
    tp.k = 5;
    p.mode = reuse_mode::eyes;
    p.fovea_deg = 0;
    index = std::make_unique<traced_index>(make_traced_index(*set, 5));
    seen = trace_points(s, left, *set, *index, g, tp);
  }
};

TEST_F(eyes_apart, WhatTheLeftEyeDidNotSeeIsTraced) {
  const traced_index& idx = *index;
  for (const reuse_distance distance : {reuse_distance::world, reuse_distance::screen}) {
    SCOPED_TRACE(label_of(reuse_distance_labels, distance));
    p.distance = distance;
    reuse_history history = history_of(seen.samples, left, *set, tp.spp);
    const reused_trace kept = trace_reusing(s, right, *set, idx, g, tp, p, history);
    const points_trace fresh = trace_points(s, right, *set, idx, g, tp);
    const point_probe now = probe_points(s, right, *set, idx, g, tp);
    const camera_frame lf = make_frame(left, 64, 48);
    ASSERT_GT(kept.report.reused, now.points.size() / 2);  // the wall both eyes see, and the quad's middle
    uint64_t disoccluded = 0, disoccluded_kept = 0, kept_wrong = 0;
    for (size_t j = 0; j < now.points.size(); ++j) {
      const uint32_t i = now.points[j];
      const bool reused = std::binary_search(kept.kept.begin(), kept.kept.end(), i);
      // The right eye sees the wall here; from the left eye the quad hides that spot.
      if (now.distance[j] > 9) {
        const glm::vec3 wall = now.where[j];
        const glm::vec3 to = glm::normalize(wall - lf.origin);
        const float t = (-2 - lf.origin.z) / to.z;  // where the left eye's ray meets the quad's plane
        const glm::vec3 at = lf.origin + t * to;
        if (at.x > -0.5f && at.x < 0.5f && at.y > -1 && at.y < 1) {
          ++disoccluded;
          // Kept, it can only be a sample of the wall beside the quad in the left view.
          if (reused) {
            EXPECT_EQ(kept.trace.samples.colour[i].r, 0.0f) << "point " << i << " kept the quad for a wall the left eye did not see";
          }
          disoccluded_kept += reused;
        }
      }
      if (reused) kept_wrong += kept.trace.samples.colour[i] != fresh.samples.colour[i];
    }
    std::printf("%llu of %zu points disoccluded, %llu of them kept (wall beside the quad), %llu kept in all\n",
                (unsigned long long)disoccluded, now.points.size(), (unsigned long long)disoccluded_kept,
                (unsigned long long)kept.report.reused);
    EXPECT_GT(disoccluded, 10u);
    EXPECT_LT(disoccluded_kept, disoccluded / 4) << disoccluded_kept << " of " << disoccluded;  // most are traced
    EXPECT_LE(kept_wrong, now.points.size() / 100) << kept_wrong << " of " << now.points.size();
    // Rays: the probes and the traced points' rays, fewer than the full trace's.
    EXPECT_EQ(kept.trace.samples.rays, kept.report.probe_rays + kept.report.traced * tp.spp);
    EXPECT_LT(kept.trace.samples.rays, fresh.samples.rays);
  }
}

// From the right eye the wall 10 m away is seen turned 2.9 (at the screen's edge) to 5.7
// degrees (ahead) from where the left eye saw it, the quad 2 m away about 28 degrees.
TEST_F(eyes_apart, AViewLimitTracesSurfacesSeenFromTooFarAround) {
  const traced_index& idx = *index;
  uint64_t kept[3];
  const double limits[] = {0, 60, 1};
  for (int i = 0; i < 3; ++i) {
    p.view_deg = limits[i];
    reuse_history history = history_of(seen.samples, left, *set, tp.spp);
    kept[i] = trace_reusing(s, right, *set, idx, {32, 24}, tp, p, history).report.reused;
  }
  EXPECT_GT(kept[0], 1000u);
  EXPECT_GT(kept[1], kept[0] / 2);  // 60 degrees: every surface, with less confidence
  EXPECT_LT(kept[1], kept[0]);
  EXPECT_EQ(kept[2], 0u);  // 1 degree: neither surface
  p.view_deg = -1;
  EXPECT_NE(validate(p).find("--reuse-view"), std::string::npos);
}

TEST_F(pipeline, EyesReuseIsDeterministicAndChangesLessThanAnotherSeed) {
  render_params p = params;
  p.spp = 4;  // a probe costs a ray a point: at 2 rays a point keeping half the points saves nothing
  p.stereo.enabled = true;
  p.stereo.ipd_mm = 63;
  p.reuse.mode = reuse_mode::eyes;
  p.reuse.fovea_deg = 3;
  render_params full = p, other_seed = p;
  full.reuse.mode = reuse_mode::none;
  other_seed.reuse.mode = reuse_mode::none;
  other_seed.seed = 2;
  stereo_renderer a(scn, p), b(scn, p), c(scn, full);
  a.use_pointset(set), b.use_pointset(set), c.use_pointset(set);
  stereo_timing ta, tb;
  const frame fa = a.foveated({30, 24}, {34, 24}, p, &ta);
  EXPECT_TRUE(same_frame(fa, b.foveated({30, 24}, {34, 24}, p, &tb)));
  EXPECT_EQ(ta.right.reuse.reused, tb.right.reuse.reused);
  EXPECT_GT(ta.right.reuse.reused, 0u);
  EXPECT_GT(ta.right.reuse.traced, 0u);  // the fovea and the edges
  EXPECT_LT(ta.right.rays, ta.left.rays);
  const frame traced = c.foveated({30, 24}, {34, 24}, full), noise = c.foveated({30, 24}, {34, 24}, other_seed);
  const double kept_error = mean_abs(fa, traced), seed_difference = mean_abs(noise, traced);
  std::printf("kept %.3f of the right eye's points, |reuse - full| %.4f, |seed 2 - full| %.4f\n",
              ta.right.reuse.reused_share(), kept_error, seed_difference);
  EXPECT_GT(kept_error, 0);
  EXPECT_LT(kept_error, seed_difference);
}

}  // namespace
}  // namespace fov
