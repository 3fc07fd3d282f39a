// Nested point sets and per-frame refinement (issue 26; docs/adaptive.md): the levels nest
// and each is a Poisson-disc set, files keep them, and an adaptive frame refines only where
// contrast would be visible, within its budget, reproducibly, and reads the finest level's
// frame where it refines everything.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include "fov/checksum.h"
#include "fov/dart_throwing.h"
#include "fov/files.h"
#include "fov/flicker.h"
#include "fov/knn_table.h"
#include "fov/nested.h"
#include "fov/pointset_io.h"
#include "fov/renderer.h"
#include "opencl_required.h"
#include "test_sets.h"

namespace fov {
namespace {

namespace fs = std::filesystem;
using fov::testing::quick_darts;
using fov::testing::small_model;

// A screen with FOVE's pixels per degree (N v = 1280): 640 x 360 pixels, +-14 degrees wide.
spacing_model fove_density_model() { return small_model(640, 360, 2.0, 1.0); }
const std::vector<double> test_scales = {1.0, 2.0, 3.0};  // finest first, as --levels

std::shared_ptr<const pointset> nested_set(uint32_t k = 6) {
  static std::shared_ptr<const pointset> cached;
  static uint32_t cached_k = 0;
  if (cached && cached_k == k) return cached;
  knn_params kp;
  kp.k = k;
  auto set = std::make_shared<pointset>(
      generate_nested_pointset(fove_density_model(), test_scales, quick_darts(11, 1500), kp, knn_storage::table));
  cached = set, cached_k = k;
  return cached;
}

TEST(nested_sets, ScalesMustIncreaseFinestFirst) {
  EXPECT_EQ(levels_problem({0.7, 1.0, 3.0}), "");
  EXPECT_NE(levels_problem({1.0}), "");               // one level is a fixed set
  EXPECT_NE(levels_problem({1.0, 1.0}), "");          // not increasing
  EXPECT_NE(levels_problem({2.0, 1.0}), "");          // decreasing
  EXPECT_NE(levels_problem({0.0, 1.0}), "");          // not positive
  EXPECT_NE(levels_problem({1.0, NAN}), "");
  EXPECT_NE(levels_problem(std::vector<double>(max_levels + 1, 1.0)), "");
}

// generate_nested_pointset (what fovbench makes): levels coarsest first, the model at the
// finest scale; scales and k it cannot honour refused.
TEST(nested_sets, GeneratedSetsNameTheirLevelsAndRefuseWhatTheyCannotMake) {
  const std::shared_ptr<const pointset> set = nested_set();
  EXPECT_EQ(set->level_scales, (std::vector<double>{3.0, 2.0, 1.0}));
  EXPECT_EQ(set->model.scale, 1.0);
  EXPECT_EQ(set->level.size(), set->points.size());
  EXPECT_EQ(stored_k(*set), 6u);
  knn_params kp;
  EXPECT_THROW(generate_nested_pointset(small_model(96, 64), {2.0, 1.0}, quick_darts(5, 1000), kp), std::invalid_argument);
  spacing_model tiny = small_model(4, 4);
  tiny.scale = 9.0;
  kp.k = uint32_t(throw_darts(tiny, quick_darts(5, 1000)).size()) + 1;  // one more than the coarsest level holds
  try {
    generate_nested_pointset(tiny, {1.0, 9.0}, quick_darts(5, 1000), kp);
    ADD_FAILURE() << "k above the coarsest level's points accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("points of the coarsest level"), std::string::npos) << e.what();
  }
}

TEST(nested_sets, TheCoarsestLevelIsTheFixedSetOfItsScale) {
  spacing_model m = small_model(96, 64);
  const dart_params d = quick_darts(5, 1000);
  const nested_points n = throw_nested_darts(m, {1.0, 2.5}, d);
  m.scale = 2.5;
  const std::vector<point> fixed = throw_darts(m, d);
  std::vector<point> coarsest;
  for (size_t i = 0; i < n.points.size(); ++i)
    if (n.level[i] == 0) coarsest.push_back(n.points[i]);
  ASSERT_EQ(coarsest.size(), fixed.size());
  for (size_t i = 0; i < fixed.size(); ++i)
    ASSERT_TRUE(coarsest[i].x == fixed[i].x && coarsest[i].y == fixed[i].y && coarsest[i].spacing == fixed[i].spacing) << i;
}

TEST(nested_sets, EveryLevelIsAPoissonDiscSetContainingTheCoarserOnes) {
  const auto set = nested_set();
  const uint32_t w = set->canvas_width(), h = set->canvas_height();
  uint64_t previous = 0;
  for (uint32_t l = 0; l < set->level_count(); ++l) {
    const std::vector<point> pts = level_points(*set, l);
    EXPECT_GT(pts.size(), previous) << "level " << l << " adds points";
    previous = pts.size();
    EXPECT_EQ(count_spacing_violations(pts, w, h), 0u) << "level " << l;
    // The spacing each point kept is its own level's at its distance (or a coarser level's).
    spacing_model m = set->model;
    m.scale = set->level_scales[l];
    for (size_t i = 0; i < set->points.size(); i += 97) {
      if (set->level[i] != l) continue;
      const point& p = set->points[i];
      EXPECT_FLOAT_EQ(p.spacing, float(point_spacing_px(m, std::hypot(double(p.x) - w / 2, double(p.y) - h / 2))));
    }
  }
  // Saturated at its own scale: a dart thrown at the finest level's spacing finds almost no room.
  EXPECT_LT(set->stats.free_fraction, 0.01);
  // Levels are sets of their own with the same neighbours as a fixed set of those points.
  const nested_levels levels = make_levels(set);
  ASSERT_EQ(levels.levels.size(), 3u);
  for (uint32_t l = 0; l < 3; ++l) {
    const pointset& v = *levels.levels[l].set;
    EXPECT_EQ(v.points.size(), level_points(*set, l).size());
    EXPECT_DOUBLE_EQ(v.model.scale, set->level_scales[l]);
    for (uint32_t y = 0; y < h; y += 37)
      for (uint32_t x = 0; x < w; x += 41) {
        uint32_t got[6], want[6] = {};
        pixel_neighbours(v, x, y, 6, got);
        // brute force over the level's points
        std::vector<std::pair<double, uint32_t>> d;
        for (uint32_t i = 0; i < v.points.size(); ++i)
          d.push_back({std::hypot(double(v.points[i].x) - (x + 0.5), double(v.points[i].y) - (y + 0.5)), i});
        std::partial_sort(d.begin(), d.begin() + 6, d.end());
        for (int j = 0; j < 6; ++j) want[j] = d[j].second;
        for (int j = 0; j < 6; ++j) ASSERT_EQ(got[j], want[j]) << "level " << l << " pixel " << x << "," << y;
      }
  }
}

TEST(nested_sets, AFileKeepsTheLevelsAndRefusesBrokenOnes) {
  const auto set = nested_set();
  const std::string path = (fs::path(::testing::TempDir()) / "fovray-nested.fovset").string();
  save_pointset(path, *set);
  const pointset back = load_pointset(path);
  EXPECT_EQ(back.level_scales, set->level_scales);
  EXPECT_EQ(back.level, set->level);
  EXPECT_EQ(back.points.size(), set->points.size());
  EXPECT_DOUBLE_EQ(back.model.scale, 1.0);

  // A level byte naming a level the set lacks, its checksum made right.
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  uint64_t levels_offset = 0;
  std::memcpy(&levels_offset, &bytes[296], 8);
  ASSERT_GT(levels_offset, 0u);
  auto rewrite = [&](std::string b, const std::string& name) {
    uint32_t crc = crc32c(reinterpret_cast<const uint8_t*>(&b[levels_offset]), set->points.size());
    std::memcpy(&b[312], &crc, 4);
    crc = crc32c(reinterpret_cast<const uint8_t*>(b.data()), 508);
    std::memcpy(&b[508], &crc, 4);
    const std::string p = (fs::path(::testing::TempDir()) / name).string();
    std::ofstream(p, std::ios::binary) << b;
    return p;
  };
  std::string bad = bytes;
  bad[levels_offset + 10] = 3;
  try {
    load_pointset(rewrite(bad, "fovray-nested-bad-level.fovset"));
    FAIL() << "a point of a level the set lacks was accepted";
  } catch (const file_error& e) {
    EXPECT_NE(std::string(e.what()).find("level 3 in a set of 3 levels"), std::string::npos) << e.what();
  }
  // Scales that do not decrease from the coarsest level.
  bad = bytes;
  const double two = 4.0;  // level 1 above level 0's 3.0
  std::memcpy(&bad[232 + 8], &two, 8);
  try {
    load_pointset(rewrite(bad, "fovray-nested-bad-scales.fovset"));
    FAIL() << "increasing level scales were accepted";
  } catch (const file_error& e) {
    EXPECT_NE(std::string(e.what()).find("decrease"), std::string::npos) << e.what();
  }
}

// A lat-long environment: `top` above the horizon, `bottom` below (bottom == top: constant).
std::string edge_envmap(float top, float bottom, const std::string& name) {
  const std::string path = (fs::path(::testing::TempDir()) / name).string();
  const int w = 512, h = 256;
  std::vector<float> px(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) px[(size_t(y) * w + x) * 3 + c] = y < h / 2 ? top : bottom;
  auto out = OIIO::ImageOutput::create(path);
  out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
  out->write_image(OIIO::TypeDesc::FLOAT, px.data());
  out->close();
  return "env:" + path;
}

struct adaptive : ::testing::Test {
  render_params params;
  void SetUp() override {
    params.spp = 2;
    params.reconstruct.k = 6;
    params.device = reconstruct_device::cpp;
    params.adaptive.enabled = true;
  }
  const gaze_point centre{320, 180};
  // A renderer of the built-in scene with the nested set in use (the params as they are now).
  std::unique_ptr<renderer> builtin_nested() {
    auto r = std::make_unique<renderer>(load_scene("builtin"), params);
    r->use_pointset(nested_set());
    return r;
  }
};

// Finer levels trace into the coarsest level's arrays (trace_more_points): the same samples as
// tracing every point in one call, and a trace placed elsewhere or a point twice is refused.
TEST(trace_more_points, TracingInTwoListsEqualsTracingThemTogether) {
  const std::unique_ptr<scene> loaded = load_scene("builtin");
  const scene& sc = *loaded;
  const camera cam = setup_camera(sc);
  const std::shared_ptr<const pointset> set = nested_set();
  trace_params tp;
  tp.spp = 2;
  tp.seed = 3;
  const gaze_point gaze{300, 200};
  std::vector<uint32_t> every, a, b;
  for (uint32_t i = 0; i < set->points.size(); i += 3) every.push_back(i);
  for (size_t j = 0; j < every.size(); ++j) (j % 2 ? b : a).push_back(every[j]);
  ASSERT_GT(b.size(), 100u);
  const points_trace whole = trace_listed_points(sc, cam, *set, every, gaze, tp);
  points_trace parts = trace_listed_points(sc, cam, *set, a, gaze, tp);
  EXPECT_EQ(trace_more_points(sc, cam, *set, b, gaze, tp, parts), uint64_t(b.size()) * tp.spp);
  EXPECT_EQ(parts.samples.traced, whole.samples.traced);
  EXPECT_EQ(parts.samples.rays, whole.samples.rays);
  EXPECT_EQ(parts.samples.colour, whole.samples.colour);
  EXPECT_EQ(parts.samples.depth, whole.samples.depth);
  EXPECT_EQ(parts.samples.hits, whole.samples.hits);
  uint32_t hit = 0;
  for (uint32_t i : every) hit += whole.samples.hits[i] > 0;
  EXPECT_GT(hit, 0u) << "the points see the scene";
  EXPECT_EQ(trace_more_points(sc, cam, *set, {}, gaze, tp, parts), 0u);
  EXPECT_THROW(trace_more_points(sc, cam, *set, {a[1]}, gaze, tp, parts), std::invalid_argument);  // traced already
  EXPECT_THROW(trace_more_points(sc, cam, *set, {1, 0}, gaze, tp, parts), std::invalid_argument);  // not ascending
  EXPECT_THROW(trace_more_points(sc, cam, *set, {uint32_t(set->points.size())}, gaze, tp, parts), std::invalid_argument);
  points_trace elsewhere = trace_listed_points(sc, cam, *set, a, {100, 100}, tp);
  EXPECT_THROW(trace_more_points(sc, cam, *set, b, gaze, tp, elsewhere), std::invalid_argument);  // placed for another gaze
}

TEST_F(adaptive, AConstantSceneRefinesNothing) {
  renderer r(load_scene(edge_envmap(0.4f, 0.4f, "fovray-flat.exr")), params);
  r.use_pointset(nested_set());
  frame_timing t;
  r.foveated(centre, params, &t);
  ASSERT_TRUE(t.adaptive);
  EXPECT_EQ(t.refinement.points_refined, 0u);
  EXPECT_EQ(t.refinement.blocks_per_level[0], r.last_refinement()->level.size());
  EXPECT_EQ(t.rays, t.refinement.rays_per_level[0]);
}

TEST_F(adaptive, AnEdgeRefinesOnlyAlongItAndMoreNearTheFovea) {
  const std::shared_ptr<const scene> scn = load_scene(edge_envmap(1.0f, 0.05f, "fovray-edge.exr"));
  const auto set = nested_set();
  const nested_levels levels = make_levels(set);
  trace_params tp;
  tp.spp = params.spp;
  tp.k = params.reconstruct.k;
  // The horizon: the screen row where the full-resolution frame turns from bright to dark.
  const camera cam = setup_camera(*scn);
  const frame full = trace_reference(*scn, cam, 640, 360, tp).image;
  int edge_y = -1;
  for (int y = 1; y < full.height && edge_y < 0; ++y)
    if (full.rgb[size_t(y) * full.width + 50].g < 0.5f && full.rgb[size_t(y - 1) * full.width + 50].g >= 0.5f) edge_y = y;
  ASSERT_GT(edge_y, 100);
  ASSERT_LT(edge_y, 260);
  const adaptive_trace a = trace_adaptive(*scn, cam, levels, centre, tp, params.adaptive);
  const refinement_map& map = a.map;
  // A block's samples lie at most the coarsest level's farthest k-th neighbour past it.
  const float reach = levels.levels[0].set->cells.max_radius;
  ASSERT_GT(reach, 0.0f);
  uint64_t refined_blocks = 0;
  for (uint32_t by = 0; by < map.blocks_y; ++by)
    for (uint32_t bx = 0; bx < map.blocks_x; ++bx) {
      if (map.level[size_t(by) * map.blocks_x + bx] == 0) continue;
      ++refined_blocks;
      const double y0 = double(map.y0 + by * refinement_block) - map.offset.y, y1 = y0 + refinement_block;
      const double gap = std::max({0.0, y0 - edge_y, edge_y - y1});
      EXPECT_LE(gap, reach) << "block " << bx << "," << by << " refined " << gap << " px from the edge";
    }
  EXPECT_GT(refined_blocks, 0u);
  EXPECT_EQ(a.report.points_refined, a.report.points_per_level[1] + a.report.points_per_level[2]);
  // The points refinement added (levels 1 and 2), in two bands of equal length along the edge.
  uint64_t near = 0, far = 0;
  for (uint32_t i : a.traced.samples.traced) {
    if (set->level[i] == 0) continue;
    const double dx = std::fabs(double(set->points[i].x) - a.traced.samples.offset.x - centre.x);
    near += dx >= 64 && dx < 176;
    far += dx >= 176 && dx < 288;
  }
  EXPECT_GT(near, far) << "near " << near << ", far " << far;
  EXPECT_GT(far, 0u);
}

TEST_F(adaptive, RefiningEverywhereGivesTheFinestLevelsFrame) {
  const std::unique_ptr<renderer> made = builtin_nested();
  renderer& r = *made;
  params.adaptive.threshold = 0;
  const frame refined = r.foveated({300, 200}, params);
  render_params fixed = params;
  fixed.adaptive.enabled = false;
  frame_timing t;
  const frame whole = r.foveated({300, 200}, fixed, &t);
  ASSERT_EQ(refined.rgb.size(), whole.rgb.size());
  for (size_t i = 0; i < whole.rgb.size(); ++i) {
    ASSERT_EQ(refined.rgb[i], whole.rgb[i]) << "pixel " << i;
    ASSERT_TRUE(refined.depth[i] == whole.depth[i] || (std::isinf(refined.depth[i]) && std::isinf(whole.depth[i]))) << i;
  }
}

TEST_F(adaptive, TheBudgetIsHonoured) {
  const std::unique_ptr<renderer> made = builtin_nested();
  renderer& r = *made;
  params.adaptive.threshold = 0.05;
  frame_timing free_run;
  r.foveated(centre, params, &free_run);
  const uint64_t coarsest = free_run.refinement.rays_per_level[0];
  ASSERT_GT(free_run.rays, coarsest + 1000) << "the scene must want refinement for the budget to bind";
  for (uint64_t budget : {coarsest + (free_run.rays - coarsest) / 3, coarsest + 1, coarsest - 1}) {
    params.adaptive.budget = budget;
    frame_timing t;
    r.foveated(centre, params, &t);
    if (budget >= coarsest) {
      EXPECT_LE(t.rays, budget);
      EXPECT_FALSE(t.refinement.budget_short);
      EXPECT_GT(t.refinement.refinements_left_out, 0u);
    } else {
      EXPECT_TRUE(t.refinement.budget_short);
      EXPECT_EQ(t.rays, coarsest) << "the coarsest level alone";
    }
  }
}

TEST_F(adaptive, TheSameSeedGivesTheSameFrameAndAStillViewKeepsItsRefinement) {
  const std::shared_ptr<const scene> scn = load_scene("builtin");
  params.adaptive.threshold = 0.2;
  params.taa = true;  // new ray positions every frame
  renderer a(scn, params), b(scn, params);
  a.use_pointset(nested_set());
  b.use_pointset(nested_set());
  frame_timing ta, tb;
  const frame fa = a.foveated(centre, params, &ta);
  const frame fb = b.foveated(centre, params, &tb);
  EXPECT_EQ(fa.rgb, fb.rgb);
  EXPECT_EQ(ta.refinement.rays_per_level, tb.refinement.rays_per_level);
  EXPECT_EQ(a.last_refinement()->level, b.last_refinement()->level);
  const std::vector<uint8_t> first = a.last_refinement()->level;
  frame_timing next;
  a.foveated(centre, params, &next);  // reseeded rays, the same view
  EXPECT_GT(next.refinement.blocks_kept, 0u);
  const std::vector<uint8_t>& second = a.last_refinement()->level;
  for (size_t i = 0; i < first.size(); ++i) ASSERT_GE(second[i], first[i]) << "block " << i << " lost its refinement";
  // A moved gaze starts afresh.
  frame_timing moved;
  a.foveated({330, 180}, params, &moved);
  EXPECT_EQ(moved.refinement.blocks_kept, 0u);
}

TEST_F(adaptive, TheDeviceRebuildsWhatTheCppPathDoes) {
  const std::shared_ptr<const scene> scn = load_scene("builtin");
  for (method m : {method::nn, method::shepard, method::rbf, method::barycentric, method::natural}) {
    params.reconstruct.how = m;
    params.adaptive.threshold = 0.2;
    render_params on_device = params;
    on_device.device = reconstruct_device::opencl;
    renderer cpp(scn, params), dev(scn, on_device);
    cpp.use_pointset(nested_set());
    dev.use_pointset(nested_set());
    const frame a = cpp.foveated(centre, params);
    frame_timing t;
    const frame b = dev.foveated(centre, on_device, &t);
    if (!t.on_device) {
      if (opencl_required()) FAIL() << "no OpenCL device, and FOV_REQUIRE_OPENCL=1: " << dev.device_problem();
      GTEST_SKIP() << "no OpenCL device: " << dev.device_problem();
    }
    ASSERT_GT(t.refinement.points_refined, 0u);
    float worst = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(a.rgb[i][c] - b.rgb[i][c]));
    EXPECT_LT(worst, 1e-4f) << method_name(m);
  }
}

TEST_F(adaptive, FlickerIsMeasuredAndAStillViewDoesNotFlicker) {
  const std::unique_ptr<renderer> made = builtin_nested();
  renderer& r = *made;
  params.adaptive.threshold = 0.2;
  flicker_params still;
  still.frames = 4, still.yaw_deg_per_frame = 0, still.gaze_px_per_frame = 0, still.full_resolution = false;
  const flicker_report a = measure_flicker(r, centre, params, still);
  EXPECT_EQ(a.raw, 0.0) << "the same rays and the same refinement every frame";
  flicker_params moving;
  moving.frames = 4, moving.full_resolution = false;
  const flicker_report b = measure_flicker(r, centre, params, moving);
  EXPECT_GT(b.raw, 0.0);
  EXPECT_TRUE(std::isfinite(b.taa));
  EXPECT_LT(b.taa, b.raw) << "TAA smooths what the turning view changes";
}

}  // namespace
}  // namespace fov
