#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <tbb/global_control.h>

#include "fov/dart_throwing.h"
#include "fov/knn_table.h"
#include "fov/trace.h"
#include "fov/usage_error.h"
#include "test_sets.h"

namespace fov {
namespace {

namespace fs = std::filesystem;

trace_params with_k(trace_params p, uint32_t k) {
  p.k = k;
  return p;
}

// A scene of one mesh whose material only emits: colours are exact, no lighting.
scene_description emitter(std::vector<glm::vec3> corners, glm::vec3 colour, material mat = {}) {
  scene_description d;
  mat.base_colour = glm::vec4(0, 0, 0, mat.base_colour.a);
  mat.emissive = colour;
  d.materials.push_back(mat);
  mesh m;
  m.positions = std::move(corners);
  m.uvs.assign(m.positions.size(), glm::vec2(0.5f));
  for (uint32_t i = 2; i < m.positions.size(); ++i) m.triangles.push_back({0, i - 1, i});
  d.meshes.push_back(m);
  d.instances.push_back({0, glm::mat4(1.0f), ""});
  d.lights.at(0).colour = glm::vec3(0);
  d.env.colour = glm::vec3(0);
  return d;
}

TEST(Camera, ProjectInvertsRayDirection) {
  const camera_frame f = make_frame(look_at({1, 2, 3}, {0, 0, -4}, 70), 320, 200);
  for (glm::vec2 s : {glm::vec2(0.5f, 0.5f), glm::vec2(160, 100), glm::vec2(319.5f, 10.25f)}) {
    const glm::vec3 p = f.origin + 7.0f * ray_direction(f, s.x, s.y);
    const glm::vec2 back = project(f, p);
    EXPECT_NEAR(back.x, s.x, 1e-3);
    EXPECT_NEAR(back.y, s.y, 1e-3);
  }
  // The screen centre looks straight ahead; the right edge is hfov / 2 off axis.
  EXPECT_NEAR(glm::dot(ray_direction(f, 160, 100), f.forward), 1.0, 1e-6);
  EXPECT_NEAR(std::acos(glm::dot(ray_direction(f, 320, 100), f.forward)), glm::radians(35.0f), 1e-5);
}

TEST(Camera, PathsInterpolateBetweenKeysAndHoldAtTheirEnds) {
  camera_path path;
  path.keys = {{10, {0, 0, 0}, {0, 0, -1}}, {20, {2, 0, 0}, {2, 0, -1}}, {20, {4, 0, 0}, {5, 0, 0}}, {30, {4, 0, 0}, {4, 1, 0}}};
  camera base = look_at({9, 9, 9}, {9, 9, 0}, 55);
  base.up = {0, 0, 1};
  const camera before = path.at(-5, base), start = path.at(10, base), mid = path.at(15, base);
  EXPECT_EQ(before.position, glm::vec3(0, 0, 0));
  EXPECT_EQ(start.position, glm::vec3(0, 0, 0));
  EXPECT_EQ(mid.position, glm::vec3(1, 0, 0));
  EXPECT_EQ(mid.forward, glm::vec3(0, 0, -1));
  // Two keys at one time: from that time on the later one holds.
  EXPECT_EQ(path.at(20, base).position, glm::vec3(4, 0, 0));
  EXPECT_EQ(path.at(20, base).forward, glm::vec3(1, 0, 0));
  // Halfway from looking along +x to looking along +y: the target's midpoint, normalised.
  EXPECT_NEAR(glm::distance(path.at(25, base).forward, glm::normalize(glm::vec3(0.5f, 0.5f, 0))), 0, 1e-6);
  EXPECT_EQ(path.at(1e9, base).forward, glm::vec3(0, 1, 0));
  // The base's field of view and up stay.
  EXPECT_EQ(mid.hfov_deg, 55);
  EXPECT_EQ(mid.up, glm::vec3(0, 0, 1));
}

TEST(Tracer, KnownTriangleHitsKnownPixels) {
  // Triangle (0,0,-5) (1,0,-5) (0,1,-5) seen from the origin with a 90-degree, 101-px screen:
  // world x maps to 50.5 + 50.5 x / 5, world y to 50.5 - 50.5 y / 5.
  scene s(emitter({{0, 0, -5}, {1, 0, -5}, {0, 1, -5}}, {1, 0, 0}));
  trace_params tp;
  tp.spp = 4;
  const frame f = trace_reference(s, look_at({0, 0, 0}, {0, 0, -1}, 90), 101, 101, tp).image;
  auto at = [&](int x, int y) { return f.rgb[size_t(y) * 101 + x]; };
  EXPECT_EQ(at(52, 48), glm::vec3(1, 0, 0));  // world (0.2, 0.2) inside
  EXPECT_NEAR(f.depth[48 * 101 + 52], 5.0f, 1e-4);
  EXPECT_EQ(at(45, 48), glm::vec3(0));        // world x < 0
  EXPECT_EQ(at(62, 48), glm::vec3(0));        // world x > 1
  EXPECT_EQ(at(52, 52), glm::vec3(0));        // world y < 0
  EXPECT_TRUE(std::isinf(f.depth[0]));
  EXPECT_EQ(f.rays, 101u * 101u * 4u);
}

// A red emitter of material `front` 2 units before the camera, a larger green one behind it at 4.
scene_description red_before_green(const material& front) {
  scene_description d = emitter({{-1, -1, -2}, {1, -1, -2}, {1, 1, -2}, {-1, 1, -2}}, {1, 0, 0}, front);
  material back;
  back.base_colour = glm::vec4(0, 0, 0, 1);
  back.emissive = {0, 1, 0};
  d.materials.push_back(back);
  mesh m = d.meshes[0];
  for (glm::vec3& p : m.positions) p = glm::vec3(4 * p.x, 4 * p.y, -4);
  m.material = 1;
  d.meshes.push_back(m);
  d.instances.push_back({1, glm::mat4(1.0f), ""});
  return d;
}

TEST(Tracer, AlphaMaskDropsHitsBelowTheCutoff) {
  for (float alpha : {0.2f, 0.8f}) {
    material front;
    front.alpha = alpha_mode::mask;
    front.alpha_cutoff = 0.5f;
    front.base_colour.a = alpha;
    scene s(red_before_green(front));
    trace_params tp;
    tp.spp = 2;
    const frame f = trace_reference(s, look_at({0, 0, 0}, {0, 0, -1}, 60), 9, 9, tp).image;
    const glm::vec3 expected = alpha < 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    EXPECT_EQ(f.rgb[4 * 9 + 4], expected) << "alpha " << alpha;
    EXPECT_NEAR(f.depth[4 * 9 + 4], alpha < 0.5f ? 4.0f : 2.0f, 1e-4);
  }
}

// glTF BLEND as stochastic transparency: each ray meets the surface with probability alpha,
// so a red emitter of alpha a in front of a green one shows a red and (1 - a) green over
// many rays, and the same frame twice is the same bit for bit (the coin is fixed by the ray).
TEST(Tracer, AlphaBlendCoversByAlphaOverManyRays) {
  for (float alpha : {0.0f, 0.25f, 0.7f, 1.0f}) {
    material front;
    front.alpha = alpha_mode::blend;
    front.base_colour.a = alpha;
    scene s(red_before_green(front));
    trace_params tp;
    tp.spp = 64;
    const frame f = trace_reference(s, look_at({0, 0, 0}, {0, 0, -1}, 40), 16, 16, tp).image;
    glm::dvec3 sum(0);
    for (const glm::vec3& c : f.rgb) sum += glm::dvec3(c);
    const glm::dvec3 mean = sum / double(f.rgb.size());
    // 16 x 16 x 64 rays, each red with probability alpha: 4 standard errors.
    const double tolerance = 4 * std::sqrt(alpha * (1 - alpha) / (16.0 * 16 * 64)) + 1e-9;
    EXPECT_NEAR(mean.r, alpha, tolerance) << "alpha " << alpha;
    EXPECT_NEAR(mean.g, 1 - alpha, tolerance) << "alpha " << alpha;
    EXPECT_EQ(mean.r + mean.g, 1.0) << "every ray meets one of the two";
    EXPECT_EQ(trace_reference(s, look_at({0, 0, 0}, {0, 0, -1}, 40), 16, 16, tp).image.rgb, f.rgb);
    std::printf("alpha %.2f: red %.4f, green %.4f (tolerance %.4f)\n", alpha, mean.r, mean.g, tolerance);
  }
}

TEST(Tracer, LeafPatternMasksPerRay) {
  material leaf;
  leaf.alpha = alpha_mode::mask;
  leaf.procedural = pattern::leaf;
  scene_description d = emitter({{-1, -1, -2}, {1, -1, -2}, {1, 1, -2}, {-1, 1, -2}}, {1, 1, 1}, leaf);
  d.meshes[0].uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  scene s(std::move(d));
  trace_params tp;
  tp.spp = 1;
  const frame f = trace_reference(s, look_at({0, 0, 0}, {0, 0, -1}, 90), 41, 41, tp).image;
  // Pixel row 11 covers v = 0.89 .. 0.94, where the leaf is at most 0.21 wide either side of u = 0.5.
  EXPECT_EQ(f.rgb[11 * 41 + 20], glm::vec3(1));  // u = 0.49 .. 0.51: inside
  EXPECT_EQ(f.rgb[11 * 41 + 15], glm::vec3(0));  // u = 0.23 .. 0.28: inside the quad, outside the leaf
  EXPECT_EQ(f.rgb[20 * 41 + 20], glm::vec3(1));  // the middle of the leaf
}

TEST(Tracer, PointsAreDeterministicAcrossFramesAndThreads) {
  pointset set;
  set.model.display = {64, 72, 1.0};
  set.points = throw_darts(set.model, {});
  set.table = build_knn_table(set.points, 128, 144, {});
  const auto s = load_scene("builtin");
  trace_params tp;
  tp.spp = 8;
  const camera cam = s->default_camera();
  point_samples a, b;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    a = trace_points(*s, cam, set, {30, 40}, with_k(tp, 20)).samples;
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    b = trace_points(*s, cam, set, {30, 40}, with_k(tp, 20)).samples;
  }
  ASSERT_EQ(a.traced, b.traced);
  EXPECT_EQ(a.traced.size(), count_traced_points(set, {30, 40}, 20).total());
  EXPECT_EQ(a.rays, a.traced.size() * 8);
  for (uint32_t i : a.traced) {
    ASSERT_EQ(a.colour[i], b.colour[i]);
    ASSERT_EQ(a.depth[i], b.depth[i]);
    ASSERT_TRUE(std::isfinite(a.colour[i].r + a.colour[i].g + a.colour[i].b));
  }
  // With the traced-point index (what the renderer uses): the same frame bit for bit.
  const point_samples indexed = trace_points(*s, cam, set, make_traced_index(set, 20), {30, 40}, with_k(tp, 20)).samples;
  ASSERT_EQ(indexed.traced, a.traced);
  for (uint32_t i : a.traced) ASSERT_EQ(indexed.colour[i], a.colour[i]);
  EXPECT_THROW(trace_points(*s, cam, set, make_traced_index(set, 5), {30, 40}, with_k(tp, 20)), std::invalid_argument)
      << "an index for another k";
  tp.seed = 2;
  const point_samples c = trace_points(*s, cam, set, {30, 40}, with_k(tp, 20)).samples;
  size_t differ = 0;
  for (uint32_t i : a.traced) differ += a.colour[i] != c.colour[i];
  EXPECT_GT(differ, a.traced.size() / 10) << "another seed must move the rays";
}

TEST(Tracer, PointRayPositionsAreTheRaysTraced) {
  // A red half-plane covering world x < 0 at z = -5: with a 90-degree, 101-px screen it
  // covers screen x < 50.5, so a point's red is the share of its rays left of 50.5.
  scene s(emitter({{-100, -100, -5}, {0, -100, -5}, {0, 100, -5}, {-100, 100, -5}}, {1, 0, 0}));
  const camera cam = look_at({0, 0, 0}, {0, 0, -1}, 90);
  pointset set;
  set.model.display = {101, 101, 1.0};
  set.points = throw_darts(set.model, {});
  set.table = build_knn_table(set.points, 202, 202, {});
  for (const auto& [mirror, sampler] : {std::pair{false, pixel_sampler::random}, std::pair{true, pixel_sampler::random},
                                        std::pair{false, pixel_sampler::sobol}, std::pair{true, pixel_sampler::sobol}}) {
    trace_params tp;
    tp.spp = 8;
    tp.mirror_x = mirror;
    tp.disc_sampler = sampler;
    const point_samples traced = trace_points(s, cam, set, {40, 50}, with_k(tp, 5)).samples;
    const std::vector<glm::vec2> at = point_ray_positions(set, traced, {40, 50}, tp);
    ASSERT_EQ(at.size(), traced.traced.size() * 8);
    size_t checked = 0, mixed = 0;
    for (size_t k = 0; k < traced.traced.size(); ++k) {
      int left = 0;
      bool ambiguous = false;
      for (size_t r = 0; r < 8; ++r) {
        left += at[k * 8 + r].x < 50.5f;
        ambiguous |= std::fabs(at[k * 8 + r].x - 50.5f) < 1e-3f;
      }
      if (ambiguous) continue;
      ASSERT_EQ(traced.colour[traced.traced[k]].r, float(left) / 8) << "point " << traced.traced[k];
      ++checked;
      mixed += left > 0 && left < 8;
    }
    EXPECT_GT(checked, traced.traced.size() / 2);
    EXPECT_GT(mixed, 10u) << "points whose discs straddle the edge test the positions themselves";
  }
}

// The concentric map keeps areas: a fine grid of the square covers the disc evenly.
TEST(Sampler, ConcentricMapIsAreaPreserving) {
  EXPECT_EQ(concentric_disc({0.5f, 0.5f}), glm::vec2(0, 0));
  EXPECT_NEAR(glm::length(concentric_disc({1.0f, 0.5f})), 1.0f, 1e-6f);
  int inner = 0, n = 0;
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 200; ++i, ++n) {
      const glm::vec2 d = concentric_disc({(i + 0.5f) / 200, (j + 0.5f) / 200});
      ASSERT_LE(glm::length(d), 1.0f + 1e-6f);
      inner += glm::length(d) < 0.5f;
    }
  EXPECT_NEAR(double(inner) / n, 0.25, 0.005);  // the inner disc of radius 1/2 holds a quarter of the area
}

// A point's colour is the mean of its disc: 16 stratified rays estimate it better than 16
// random ones (against 1024 random rays), and the positions stay inside the disc.
TEST(Sampler, SobolDiscsConvergeFasterThanRandomOnes) {
  const auto s = load_scene("builtin");
  const camera cam = s->default_camera();
  const std::shared_ptr<const pointset> set = [] {
    auto p = std::make_shared<pointset>();
    p->model.display = {96, 108, 1.0};
    p->points = throw_darts(p->model, {});
    p->table = build_knn_table(p->points, 192, 216, {});
    return std::shared_ptr<const pointset>(p);
  }();
  trace_params tp;
  tp.k = 5;
  tp.spp = 1024;
  const point_samples truth = trace_points(*s, cam, *set, {48, 54}, tp).samples;
  auto rmse = [&](const point_samples& x) {
    double sum = 0;
    for (uint32_t i : x.traced) {
      const glm::vec3 d = x.colour[i] - truth.colour[i];
      sum += double(glm::dot(d, d)) / 3;
    }
    return std::sqrt(sum / double(x.traced.size()));
  };
  tp.spp = 16;
  tp.seed = 5;
  const point_samples random = trace_points(*s, cam, *set, {48, 54}, tp).samples;
  tp.disc_sampler = pixel_sampler::sobol;
  const point_samples sobol = trace_points(*s, cam, *set, {48, 54}, tp).samples;
  EXPECT_LT(rmse(sobol), 0.7 * rmse(random)) << rmse(sobol) << " vs " << rmse(random);
  const std::vector<glm::vec2> at = point_ray_positions(*set, sobol, {48, 54}, tp);
  const canvas_offset o = sobol.offset;
  for (size_t k = 0; k < sobol.traced.size(); ++k) {
    const point& p = set->points[sobol.traced[k]];
    for (size_t r = 0; r < 16; ++r)
      ASSERT_LE(glm::distance(at[k * 16 + r], glm::vec2(p.x - float(o.x), p.y - float(o.y))), p.spacing * 1.0001f);
  }
  EXPECT_EQ(trace_points(*s, cam, *set, {48, 54}, tp).samples.colour, sobol.colour);  // deterministic
}

TEST(Tracer, ReferenceTileTimesCoverTheScreenAndChangeNothing) {
  const auto s = load_scene("builtin");
  trace_params tp;
  tp.spp = 2;
  const frame plain = trace_reference(*s, s->default_camera(), 37, 20, tp).image;
  tp.tile_costs = true;
  const reference_trace timed = trace_reference(*s, s->default_camera(), 37, 20, tp);
  EXPECT_EQ(plain.rgb, timed.image.rgb);
  const std::vector<double>& tiles = timed.stats.tile_seconds;
  ASSERT_EQ(tiles.size(), size_t(5 * 3));  // ceil(37 / 8) x ceil(20 / 8)
  for (double t : tiles) EXPECT_GT(t, 0.0);
}

// Rays falling with eccentricity on the full pixel grid (issue 24). A small display seen from
// far (v = 100: 112 ppd) at scale 10, so the acuity model's spacing grows across its few pixels.
ray_falloff test_falloff(int w, int h, uint32_t floor) {
  ray_falloff f;
  f.model.display = {w, h, 100.0};
  f.model.scale = 10;
  f.gaze = {w * 0.3, h * 0.6};
  f.floor = floor;
  return f;
}

// A camera per screen line (trace_params::lines, a rolling display's view).
line_cameras same_camera_on_every_line(const camera& c, bool columns, int lines) {
  line_cameras l;
  l.columns = columns;
  l.cameras.assign(size_t(lines), c);
  return l;
}

TEST(LineCameras, OneCameraOnEveryLineIsTheFrameBitForBit) {
  const auto s = load_scene("builtin");
  const camera cam = s->default_camera();
  trace_params tp;
  tp.spp = 3;
  const frame global = trace_reference(*s, cam, 48, 30, tp).image;
  for (bool columns : {false, true}) {
    trace_params lined = tp;
    lined.lines = same_camera_on_every_line(cam, columns, columns ? 48 : 30);
    const frame f = trace_reference(*s, look_at({7, 7, 7}, {0, 0, 0}, 20), 48, 30, lined).image;  // the argument unused
    EXPECT_EQ(f.rgb, global.rgb);
    EXPECT_EQ(f.depth, global.depth);
  }
  pointset set;
  set.model.display = {64, 72, 1.0};
  set.points = throw_darts(set.model, {});
  set.table = build_knn_table(set.points, 128, 144, {});
  const point_samples a = trace_points(*s, cam, set, {30, 40}, tp).samples;
  trace_params lined = tp;
  lined.lines = same_camera_on_every_line(cam, false, 72);
  const point_samples b = trace_points(*s, cam, set, {30, 40}, lined).samples;
  ASSERT_EQ(a.traced, b.traced);
  EXPECT_EQ(a.colour, b.colour);
  EXPECT_EQ(a.depth, b.depth);
}

TEST(LineCameras, EachLineIsSeenFromItsOwnCamera) {
  const auto s = load_scene("builtin");
  const camera first = s->default_camera();
  camera second = first;  // turned and moved: every pixel of the scene changes
  second.position += glm::vec3(0.3f, 0.1f, 0);
  second.forward = glm::normalize(first.forward + glm::vec3(0.2f, -0.05f, 0));
  trace_params tp;
  tp.spp = 2;
  const int w = 40, h = 30;
  const frame a = trace_reference(*s, first, w, h, tp).image, b = trace_reference(*s, second, w, h, tp).image;
  for (bool columns : {false, true}) {
    const int lines = columns ? w : h, split = lines / 3;
    trace_params lined = tp;
    lined.lines = same_camera_on_every_line(first, columns, lines);
    for (int i = split; i < lines; ++i) lined.lines.cameras[size_t(i)] = second;
    const frame f = trace_reference(*s, first, w, h, lined).image;
    int differing = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        const frame& own = (columns ? x : y) < split ? a : b;
        EXPECT_EQ(f.rgb[i], own.rgb[i]) << x << "," << y;
        EXPECT_EQ(f.depth[i], own.depth[i]) << x << "," << y;
        differing += a.rgb[i] != b.rgb[i];
      }
    EXPECT_GT(differing, w * h / 2);  // the two cameras see different images
    lined.lines.cameras.pop_back();
    EXPECT_THROW(trace_reference(*s, first, w, h, lined), std::invalid_argument);
  }
}

TEST(RayFalloff, AFlatRuleIsTheFullResolutionFrameBitForBit) {
  const auto s = load_scene("builtin");
  for (pixel_sampler sampler : {pixel_sampler::sobol, pixel_sampler::random}) {
    trace_params tp;
    tp.spp = 6;
    tp.sampler = sampler;
    const frame full = trace_reference(*s, s->default_camera(), 48, 30, tp).image;
    tp.falloff = test_falloff(48, 30, 6);
    const frame flat = trace_reference(*s, s->default_camera(), 48, 30, tp).image;
    EXPECT_EQ(flat.rgb, full.rgb);
    EXPECT_EQ(flat.depth, full.depth);
    EXPECT_EQ(flat.rays, full.rays);
  }
}

TEST(RayFalloff, EachPixelCastsItsRuleAndIsThatManyRaysOfTheFullFrame) {
  const auto s = load_scene("builtin");
  const int w = 64, h = 40;
  trace_params tp;
  tp.spp = 16;
  tp.falloff = test_falloff(w, h, 2);
  const falloff_rule rule = make_falloff_rule(*tp.falloff, tp.spp);
  // The rule as its equation says, away from its thresholds, and falling with distance.
  const double p0 = point_spacing_px(tp.falloff->model, 0);
  uint32_t previous = rule.rays_at(0);
  EXPECT_EQ(previous, 16u);
  for (double d = 0; d < 150; d += 0.37) {
    const double q = p0 / point_spacing_px(tp.falloff->model, d);
    const double exact = std::clamp(16.0 * q * q, 2.0, 16.0);
    const uint32_t n = rule.rays_at(d);
    if (std::fabs(exact - std::floor(exact) - 0.5) > 1e-6) {
      EXPECT_EQ(n, uint32_t(std::llround(exact))) << d;
    }
    EXPECT_LE(n, previous);
    previous = n;
  }
  EXPECT_EQ(rule.rays_at(1e6), 2u) << "the floor holds however far";
  const reference_trace fall = trace_reference(*s, s->default_camera(), w, h, tp);
  // Every pixel is the full-resolution frame at its own ray count (the first n of its rays),
  // and the frame's rays are what the rule gives.
  std::map<uint32_t, frame> at;
  uint64_t rays = 0;
  std::set<uint32_t> counts;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint32_t n = rule.rays_at(std::hypot(x + 0.5 - tp.falloff->gaze.x, y + 0.5 - tp.falloff->gaze.y));
      rays += n;
      counts.insert(n);
      if (!at.count(n)) {
        trace_params flat = tp;
        flat.falloff.reset();
        flat.spp = n;
        at[n] = trace_reference(*s, s->default_camera(), w, h, flat).image;
      }
      const size_t i = size_t(y) * w + x;
      ASSERT_EQ(fall.image.rgb[i], at[n].rgb[i]) << x << "," << y << " n=" << n;
    }
  EXPECT_EQ(fall.image.rays, rays);
  EXPECT_GE(counts.size(), 4u) << "the test display spans several ray counts";
  EXPECT_LT(rays, uint64_t(w) * h * 16);
  EXPECT_GT(rays, uint64_t(w) * h * 2);
  // Out of range: refused.
  trace_params bad = tp;
  bad.falloff->floor = 17;
  EXPECT_THROW(trace_reference(*s, s->default_camera(), w, h, bad), std::invalid_argument);
  bad.falloff->floor = 0;
  EXPECT_THROW(trace_reference(*s, s->default_camera(), w, h, bad), std::invalid_argument);
  bad = tp;
  EXPECT_THROW(trace_reference(*s, s->default_camera(), w + 1, h, bad), std::invalid_argument) << "another display's rule";
}

// A narrow view far down the built-in floor at 512 rays a pixel: the checker's box filter,
// tiny there, cancelled to noise in float and pushed 2400 colour values of this frame below
// zero (found at 70 ppd: fovbench compare refused the 512-spp reference).
TEST(Tracer, FilteredCheckerStaysInRangeForTinyFootprints) {
  const auto s = load_scene("builtin");
  trace_params tp;
  tp.spp = 512;
  const frame f = trace_reference(*s, look_at({0, 1.6f, 4}, {0, 0, -3.69f}, 0.9066f), 64, 64, tp).image;
  size_t negative = 0;
  for (const glm::vec3& c : f.rgb)
    for (int i = 0; i < 3; ++i) negative += !(c[i] >= 0);
  EXPECT_EQ(negative, 0u);
}

// The first 2^m samples of the scrambled (0,2)-sequence put exactly one sample in every
// cell of every 2^a x 2^(m-a) grid, whatever the scrambles.
TEST(Sampler, OwenSobolIsStratifiedForEveryScramble) {
  for (uint32_t seed : {0u, 1u, 0xdeadbeefu, 0x12345678u})
    for (int m : {2, 4, 6, 8}) {
      const uint32_t n = 1u << m;
      for (int a = 0; a <= m; ++a) {
        const uint32_t nx = 1u << a, ny = 1u << (m - a);
        std::vector<int> cells(n, 0);
        for (uint32_t s = 0; s < n; ++s) {
          const glm::vec2 u = owen_sobol_2d(s, seed, seed * 2654435761u + 7);
          ASSERT_TRUE(u.x >= 0 && u.x < 1 && u.y >= 0 && u.y < 1);
          ++cells[size_t(uint32_t(u.y * float(ny)) * nx + uint32_t(u.x * float(nx)))];
        }
        for (int c : cells) ASSERT_EQ(c, 1) << "seed " << seed << " m " << m << " a " << a;
      }
    }
  EXPECT_NE(owen_sobol_2d(0, 1, 2).x, owen_sobol_2d(0, 3, 2).x);  // the scramble moves the points
}

// Against a 1024-spp reference, 16 Sobol rays per pixel err far less than 16 random
// ones; two Sobol references with different seeds are independent estimates (they differ).
TEST(Sampler, SobolReferencesConvergeFasterThanRandomOnes) {
  const auto s = load_scene("builtin");
  const camera cam = s->default_camera();
  trace_params tp;
  tp.spp = 1024;
  const frame truth = trace_reference(*s, cam, 64, 40, tp).image;
  auto rmse = [&](const frame& f) {
    double sum = 0;
    for (size_t i = 0; i < f.rgb.size(); ++i) {
      const glm::vec3 d = f.rgb[i] - truth.rgb[i];
      sum += double(glm::dot(d, d)) / 3;
    }
    return std::sqrt(sum / double(f.rgb.size()));
  };
  tp.spp = 16;
  tp.seed = 2;
  const frame sobol = trace_reference(*s, cam, 64, 40, tp).image;
  tp.seed = 3;
  const frame sobol2 = trace_reference(*s, cam, 64, 40, tp).image;
  tp.sampler = pixel_sampler::random;
  const frame random = trace_reference(*s, cam, 64, 40, tp).image;
  EXPECT_LT(rmse(sobol), 0.6 * rmse(random)) << rmse(sobol) << " vs " << rmse(random);
  EXPECT_NE(sobol.rgb, sobol2.rgb);
  EXPECT_GT(rmse(sobol2), 0.0);
}

// A white diffuse quad facing the light: under the default light it stays below 1 (no
// clipping on display); exposure scales every colour by 2^EV exactly; a sun given in the
// params replaces the scene's.
TEST(Lighting, DefaultLightDoesNotClipWhiteAndExposureScales) {
  scene_description d;
  material white;
  white.base_colour = glm::vec4(1);
  d.materials.push_back(white);
  mesh m;
  m.positions = {{-5, -5, -3}, {5, -5, -3}, {5, 5, -3}, {-5, 5, -3}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  m.uvs.assign(4, glm::vec2(0.5f));
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  d.meshes.push_back(m);
  d.instances.push_back({0, glm::mat4(1.0f), ""});
  d.lights.at(0).direction = {0, 0, 1};  // straight at the quad: the brightest it can be
  const scene s(d);
  const camera cam = look_at({0, 0, 0}, {0, 0, -1}, 60);
  trace_params tp;
  tp.spp = 1;
  const frame plain = trace_reference(s, cam, 4, 4, tp).image;
  for (const glm::vec3& c : plain.rgb) {
    EXPECT_GT(c.r, 0.8f);
    EXPECT_LT(std::max({c.r, c.g, c.b}), 1.0f);
  }
  tp.exposure_ev = 1;
  const frame brighter = trace_reference(s, cam, 4, 4, tp).image;
  for (size_t i = 0; i < plain.rgb.size(); ++i) EXPECT_EQ(brighter.rgb[i], 2.0f * plain.rgb[i]);
  tp.exposure_ev = 0;
  light sideways;
  sideways.direction = glm::normalize(glm::vec3(1, 0, 1));  // 45 degrees off the normal
  sideways.colour = d.lights.at(0).colour;
  tp.sun = sideways;
  const frame lit = trace_reference(s, cam, 4, 4, tp).image;
  const glm::vec3 ambient = plain.rgb[0] - d.lights.at(0).colour;  // direct light at normal incidence is the irradiance
  EXPECT_NEAR(lit.rgb[0].r, ambient.r + d.lights.at(0).colour.r * std::sqrt(0.5f), 1e-4f);
  tp.exposure_ev = 21;
  EXPECT_THROW(trace_reference(s, cam, 4, 4, tp), std::invalid_argument);
}

TEST(Tracer, MirroredPatternsTraceTheSetPlacedForTheMirroredGaze) {
  pointset set;
  set.model.display = {48, 40, 1.0};
  set.points = throw_darts(set.model, {});
  set.table = build_knn_table(set.points, 96, 80, {});
  const auto s = load_scene("builtin");
  const camera cam = s->default_camera();
  trace_params tp;
  tp.spp = 2;
  tp.mirror_x = true;
  const point_samples m = trace_points(*s, cam, set, {10, 30}, with_k(tp, 5)).samples;
  tp.mirror_x = false;
  const point_samples plain = trace_points(*s, cam, set, {48 - 10, 30}, with_k(tp, 5)).samples;
  EXPECT_TRUE(m.mirror_x);
  EXPECT_FALSE(m.mirror_y);
  EXPECT_EQ(m.offset.x, plain.offset.x);
  EXPECT_EQ(m.traced, plain.traced);  // the same points ...
  size_t differ = 0;
  for (uint32_t i : m.traced) differ += m.colour[i] != plain.colour[i];
  EXPECT_GT(differ, m.traced.size() / 2);  // ... seen at mirrored screen positions
}

// A grid-fovea set whose model's spacing grows across its screen (made once): grid points
// and darts both, for the grid's pixel rays and for rays per point falling with
// eccentricity (trace_params::ray_floor, issue 24).
const pointset& grid_fovea_set() {
  static const pointset set = [] {
    knn_params kp;
    kp.k = 5;
    return generate_pointset(testing::partial_grid_model(), testing::grid_darts(), kp);
  }();
  return set;
}
const gaze_point off_centre_gaze{50.3, 41.7};  // off the centre and off the pixel grid

TEST(PointRays, AFlatRuleIsTheThesissTraceBitForBit) {
  const auto s = load_scene("builtin");
  const pointset& set = grid_fovea_set();
  const gaze_point g = off_centre_gaze;
  for (const bool mirror : {false, true})
    for (const pixel_sampler sampler : {pixel_sampler::random, pixel_sampler::sobol}) {
      trace_params tp;
      tp.spp = 6;
      tp.k = 5;
      tp.mirror_x = tp.mirror_y = mirror;
      tp.disc_sampler = sampler;
      const point_samples thesis = trace_points(*s, s->default_camera(), set, g, tp).samples;
      tp.ray_floor = 6;
      const point_samples flat = trace_points(*s, s->default_camera(), set, g, tp).samples;
      EXPECT_EQ(flat.traced, thesis.traced);
      EXPECT_EQ(flat.colour, thesis.colour);
      EXPECT_EQ(flat.depth, thesis.depth);
      EXPECT_EQ(flat.hits, thesis.hits);
      EXPECT_EQ(flat.rays, thesis.rays);
      EXPECT_EQ(flat.rays, thesis.traced.size() * 6);
    }
}

TEST(PointRays, EachPointCastsItsRuleAndIsThatManyRaysOfAFlatTrace) {
  const auto s = load_scene("builtin");
  const camera cam = s->default_camera();
  const pointset& set = grid_fovea_set();
  const int w = set.model.display.width;
  const gaze_point g = off_centre_gaze;
  for (const bool mirror : {false, true}) {
    trace_params tp;
    tp.spp = 16;
    tp.k = 5;
    tp.ray_floor = 2;
    tp.mirror_x = mirror;
    const falloff_rule rule = point_ray_rule(set, g, tp.spp, tp.ray_floor);
    const point_samples fall = trace_points(*s, cam, set, g, tp).samples;
    const std::vector<glm::vec2> at = point_ray_positions(set, fall, g, tp);
    // The rule at each point's screen position; its rays are the first n of the flat trace's.
    std::map<uint32_t, point_samples> flat_at;
    uint64_t rays = 0;
    size_t grid = 0, darts = 0, next = 0;
    std::set<uint32_t> counts;
    for (size_t k = 0; k < fall.traced.size(); ++k) {
      const uint32_t i = fall.traced[k];
      const point& p = set.points[i];
      float x = p.x - float(fall.offset.x), y = p.y - float(fall.offset.y);
      if (mirror) x = float(w) - x;
      const uint32_t n = rule.rays_at(std::hypot(double(x) - g.x, double(y) - g.y));
      rays += n;
      counts.insert(n);
      (is_grid_point(set, p) ? grid : darts) += 1;
      if (!flat_at.count(n)) {
        trace_params flat = tp;
        flat.ray_floor = 0;
        flat.spp = n;
        flat_at[n] = trace_points(*s, cam, set, g, flat).samples;
      }
      ASSERT_EQ(fall.colour[i], flat_at[n].colour[i]) << "point " << i << " n=" << n;
      ASSERT_EQ(fall.hits[i], flat_at[n].hits[i]);
      for (uint32_t r = 0; r < n; ++r, ++next)  // its rays, in order, inside its disc or pixel
        ASSERT_LE(glm::distance(at[next], glm::vec2(x, y)), std::max(p.spacing, 0.71f) * 1.0001f);
    }
    EXPECT_EQ(next, at.size()) << "point_ray_positions lists the rays the rule gives, no more";
    EXPECT_EQ(fall.rays, rays);
    EXPECT_GE(counts.size(), 4u) << "the set spans several ray counts";
    EXPECT_GT(grid, 500u);
    EXPECT_GT(darts, 500u);
    EXPECT_LT(rays, fall.traced.size() * 16);  // the budget: at most spp a point, at least the floor
    EXPECT_GE(rays, fall.traced.size() * 2);
    EXPECT_EQ(*counts.begin(), 2u) << "the periphery reaches the floor";
    EXPECT_EQ(*counts.rbegin(), 16u);
  }
  // Out of range: refused.
  trace_params bad;
  bad.spp = 4;
  bad.k = 5;
  bad.ray_floor = 5;
  EXPECT_THROW(trace_points(*s, cam, set, g, bad), std::invalid_argument);
}

// The hybrid (a grid fovea whose points' rays fall, darts beyond): each grid point is the
// full grid's falloff frame's pixel (same model, gaze, spp and floor) bit for bit.
// Where grid point i of a trace lands on the screen (placed and mirrored as the trace was),
// or nothing when it is not a grid point or lies off the screen.
std::optional<glm::vec2> grid_point_on_screen(const pointset& set, const point_samples& traced, uint32_t i) {
  const point& p = set.points[i];
  if (!is_grid_point(set, p)) return std::nullopt;
  const float w = float(set.model.display.width), h = float(set.model.display.height);
  float x = p.x - float(traced.offset.x), y = p.y - float(traced.offset.y);
  if (traced.mirror_x) x = w - x;
  if (traced.mirror_y) y = h - y;
  if (x < 0 || y < 0 || x >= w || y >= h) return std::nullopt;
  return glm::vec2(x, y);
}

TEST(PointRays, GridPointsAreTheFalloffFramesPixels) {
  // In every TAA pattern: pattern m (mirror_x + 2 mirror_y) places the set mirrored, and a
  // grid point casts its pixel's samples m n .. (m + 1) n - 1, as that pixel does in the full
  // grid's frame in pattern m (so TAA over either blends the same four sample sets).
  const auto s = load_scene("builtin");
  const camera cam = s->default_camera();
  const pointset& set = grid_fovea_set();
  const int w = set.model.display.width, h = set.model.display.height;
  const gaze_point g = off_centre_gaze;
  frame first;
  for (uint32_t pattern = 0; pattern < 4; ++pattern) {
    trace_params tp;
    tp.spp = 16;
    tp.k = 5;
    tp.ray_floor = 1;
    tp.mirror_x = pattern & 1, tp.mirror_y = pattern & 2;
    const point_samples hybrid = trace_points(*s, cam, set, g, tp).samples;
    trace_params full = tp;
    full.falloff = ray_falloff{set.model, g, 1};
    const frame fall = trace_reference(*s, cam, w, h, full).image;
    size_t grid = 0, below_spp = 0;
    const falloff_rule rule = point_ray_rule(set, g, 16, 1);
    for (uint32_t i : hybrid.traced) {
      const std::optional<glm::vec2> at = grid_point_on_screen(set, hybrid, i);
      if (!at) continue;
      const float x = at->x, y = at->y;
      ASSERT_EQ(hybrid.colour[i], fall.rgb[size_t(y) * w + size_t(x)]) << x << "," << y << " in pattern " << pattern;
      ++grid;
      below_spp += rule.rays_at(std::hypot(x - g.x, y - g.y)) < 16;
    }
    EXPECT_GT(grid, 500u) << "pattern " << pattern;
    EXPECT_GT(below_spp, 100u) << "the grid's own rays fall too, or the test proves nothing about the rule";
    // The patterns cast other samples: the frames differ.
    if (pattern == 0) first = fall;
    else EXPECT_NE(fall.rgb, first.rgb) << "pattern " << pattern << " cast pattern 0's samples";
  }
}

// Writes a 64x32 lat-long image whose texels are coloured by the axis closest to their direction.
std::string write_axis_envmap(const fs::path& dir) {
  const glm::vec3 colours[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};  // +x -x +y -y +z -z
  const int w = 64, h = 32;
  std::vector<float> px(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Inverse of the documented mapping: s = 0.5 + atan2(x, -z) / 2pi, t = acos(y) / pi.
      const float phi = (float(x) + 0.5f) / w * 2 * 3.14159265f - 3.14159265f, theta = (float(y) + 0.5f) / h * 3.14159265f;
      const glm::vec3 d(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
      int best = 0;
      float score = -2;
      for (int a = 0; a < 6; ++a) {
        glm::vec3 axis(0);
        axis[a / 2] = a % 2 ? -1.f : 1.f;
        if (glm::dot(d, axis) > score) score = glm::dot(d, axis), best = a;
      }
      for (int c = 0; c < 3; ++c) px[(size_t(y) * w + x) * 3 + c] = colours[best][c];
    }
  const std::string path = (dir / "axes.exr").string();
  auto out = OIIO::ImageOutput::create(path);
  out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
  out->write_image(OIIO::TypeDesc::FLOAT, px.data());
  out->close();
  return path;
}

TEST(FovealGrid, MirroredPatternsCastTheNextSamplesOfEachPixel) {
  // Pattern n (mirror_x + 2 mirror_y) casts samples [n spp, (n + 1) spp) of its pixel's
  // sequence: the four patterns' mean is the full-resolution frame at 4 spp. An emitting
  // half-plane with a slanted edge: a pixel on the edge is the share of its rays on one side.
  scene s(emitter({{-100, -100, -5}, {0.4f, -100, -5}, {-0.4f, 100, -5}, {-100, 100, -5}}, {1, 0, 0}));
  const camera cam = look_at({0, 0, 0}, {0, 0, -1}, 90);
  const pointset& set = grid_fovea_set();
  const int w = set.model.display.width, h = set.model.display.height;
  const gaze_point g = screen_centre(set.model.display);
  trace_params tp;
  tp.spp = 2;
  tp.k = 5;
  std::vector<float> mean(size_t(w) * h, 0);
  std::vector<int> patterns(size_t(w) * h, 0);
  for (int n = 0; n < 4; ++n) {
    tp.mirror_x = n & 1, tp.mirror_y = n & 2;
    const point_samples ps = trace_points(s, cam, set, g, tp).samples;
    for (uint32_t i : ps.traced) {
      const std::optional<glm::vec2> on = grid_point_on_screen(set, ps, i);
      if (!on) continue;
      const size_t at = size_t(on->y) * w + size_t(on->x);
      mean[at] += 0.25f * ps.colour[i].r;
      ++patterns[at];
    }
  }
  tp.mirror_x = tp.mirror_y = false;
  tp.spp = 8;
  const frame full = trace_reference(s, cam, w, h, tp).image;
  tp.spp = 2;
  const frame two = trace_reference(s, cam, w, h, tp).image;
  size_t grid = 0, on_edge = 0, moved = 0, same = 0;
  for (size_t i = 0; i < mean.size(); ++i) {
    if (patterns[i] == 0) continue;
    ASSERT_EQ(patterns[i], 4) << "every grid pixel in every pattern";
    ++grid;
    on_edge += full.rgb[i].r > 0 && full.rgb[i].r < 1;
    moved += full.rgb[i].r != two.rgb[i].r;
    same += mean[i] == full.rgb[i].r;
  }
  EXPECT_GT(grid, 2000u);
  EXPECT_GT(on_edge, 40u);
  EXPECT_GT(moved, 10u) << "more samples must change some edge pixels, or the test proves nothing";
  EXPECT_EQ(same, grid);
}

TEST(Tracer, EnvironmentSceneReturnsTheImageAlongEachAxis) {
  const fs::path dir = fs::temp_directory_path() / ("fovray-env-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const auto s = load_scene("env:" + write_axis_envmap(dir));
  const glm::vec3 colours[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
  trace_params tp;
  tp.spp = 1;
  for (int a = 0; a < 6; ++a) {
    glm::vec3 axis(0);
    axis[a / 2] = a % 2 ? -1.f : 1.f;
    const glm::vec3 up = a / 2 == 1 ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
    const frame f = trace_reference(*s, look_at({0, 0, 0}, axis, 5, up), 3, 3, tp).image;
    const glm::vec3 c = f.rgb[4];
    EXPECT_NEAR(c.r, colours[a].r, 0.02) << "axis " << a;
    EXPECT_NEAR(c.g, colours[a].g, 0.02) << "axis " << a;
    EXPECT_NEAR(c.b, colours[a].b, 0.02) << "axis " << a;
  }
  fs::remove_all(dir);
}

// Writes a w x h lat-long checker of single texels, 0 and 1 (8-bit: sRGB-decoded, still
// 0 and 1), as dir/checker.png, and returns its path.
std::string write_texel_checker(const fs::path& dir, int w, int h) {
  fs::create_directories(dir);
  std::vector<uint8_t> px(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) px[(size_t(y) * w + x) * 3 + c] = (x + y) % 2 ? 255 : 0;
  const std::string path = (dir / "checker.png").string();
  auto out = OIIO::ImageOutput::create(path);
  out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  out->write_image(OIIO::TypeDesc::UINT8, px.data());
  out->close();
  return path;
}

TEST(Tracer, EnvironmentLookupsAreFilteredByTheRayFootprint) {
  // Sharp rays read single texels of a texel checker; a wide footprint reads the mean, 0.5.
  const fs::path dir = fs::temp_directory_path() / ("fovray-envf-" + std::to_string(getpid()));
  const int h = 128;
  const auto s = load_scene("env:" + write_texel_checker(dir, 256, h));
  trace_params tp;
  tp.spp = 1;
  // 8 x 4 pixels over 120 degrees: each pixel spans about 15 degrees, some 10 texels.
  const frame wide = trace_reference(*s, look_at({0, 0, 0}, {0, 0, -1}, 120), 8, 4, tp).image;
  for (const glm::vec3& c : wide.rgb) EXPECT_NEAR(c.g, 0.5f, 0.05f);
  // 2000 pixels over 90 degrees along the centre of texel row 64: far below a texel, so
  // bilinear between texel centres, reaching 0 and 1 (the mean would be 0.5 throughout).
  const float below = std::tan(0.5f * 3.14159265f / h);
  const frame sharp = trace_reference(*s, look_at({0, 0, 0}, {0, -below, -1}, 90), 2000, 1, tp).image;
  float lo = 1, hi = 0;
  for (const glm::vec3& c : sharp.rgb) lo = std::min(lo, c.g), hi = std::max(hi, c.g);
  EXPECT_LT(lo, 0.05f);
  EXPECT_GT(hi, 0.95f);
  fs::remove_all(dir);
}

TEST(Tracer, PointFootprintPrefiltersTheDiscAndPixelFootprintDoesNot) {
  // One ray per point over a texel checker seen through 30 degrees on 64 px (a pixel is a
  // third of a texel). With the disc footprint a point p pixels apart reads the mean over
  // about 2p / 3 texels; with a pixel's footprint it reads single texels, 0 to 1.
  const fs::path dir = fs::temp_directory_path() / ("fovray-envp-" + std::to_string(getpid()));
  const auto s = load_scene("env:" + write_texel_checker(dir, 256, 128));
  // A display seen from 600 screen widths: the acuity model asks for about 9 px spacing.
  pointset set;
  set.model.display = {64, 72, 600.0};
  set.points = throw_darts(set.model, {});
  set.table = build_knn_table(set.points, 128, 144, {});
  const camera cam = look_at({0, 0, 0}, {0, 0, -1}, 30);
  trace_params tp;
  tp.spp = 1;
  const point_samples disc = trace_points(*s, cam, set, {32, 36}, with_k(tp, 5)).samples;
  tp.footprint = texture_footprint::pixel;
  const point_samples pixel = trace_points(*s, cam, set, {32, 36}, with_k(tp, 5)).samples;
  ASSERT_EQ(disc.traced, pixel.traced);
  double off_disc = 0, off_pixel = 0;  // mean distance from the checker's mean, 0.5
  size_t wide = 0;
  for (uint32_t i : disc.traced) {
    if (set.points[i].spacing < 6) continue;  // at least 4 texels wide
    off_disc += std::fabs(disc.colour[i].g - 0.5), off_pixel += std::fabs(pixel.colour[i].g - 0.5);
    ++wide;
  }
  ASSERT_GT(wide, 20u);
  off_disc /= double(wide), off_pixel /= double(wide);
  EXPECT_LT(off_disc, 0.02);   // the mean over several texels
  EXPECT_GT(off_pixel, 0.08);  // bilinear between 0 and 1 texels: 0.125 on average
  fs::remove_all(dir);
}

TEST(Tracer, MissingTexturesWarnOnceAndFallBack) {
  const fs::path dir = fs::temp_directory_path() / ("fovray-obj-" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "quad.mtl") << "newmtl a\nKd 0.2 0.4 0.6\nmap_Kd missing.png\nnewmtl b\nKd 1 1 1\nmap_Kd missing.png\n";
  std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\nv -1 -1 -3\nv 1 -1 -3\nv 1 1 -3\nv -1 1 -3\nv 0 0 -3\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                     "usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 3/3 4/4\nf 5 5 5\n";
  const auto s = load_scene((dir / "quad.obj").string());
  int missing = 0, degenerate = 0;
  for (const std::string& w : s->warnings()) {
    missing += w.find("missing.png is missing") != std::string::npos;
    degenerate += w.find("degenerate") != std::string::npos;
  }
  EXPECT_EQ(missing, 1) << "one warning per missing file";
  EXPECT_EQ(degenerate, 1);
  trace_params tp;
  tp.spp = 1;
  const frame f = trace_reference(*s, look_at({0, 0, 0}, {0, 0, -1}, 60), 5, 5, tp).image;
  EXPECT_GT(f.rgb[12].b, f.rgb[12].r) << "falls back to Kd (0.2, 0.4, 0.6)";
  fs::remove_all(dir);
  EXPECT_THROW(load_scene((dir / "nothing.gltf").string()), std::runtime_error);
}

// Textures that exist but cannot be read warn once each, naming the file and the reason,
// and fall back to the material's factors: an empty file (a failed download), a directory,
// a FIFO (whose open would block), a file that is not an image.
// glTF indices past the vertex count: Assimp drops such faces with only a log line (the
// image changed without a word); the loader refuses the file instead, naming it.
TEST(Tracer, OutOfRangeGltfIndicesAreRefused) {
  const fs::path dir = fs::temp_directory_path() / ("fovray-idx-" + std::to_string(getpid()));
  fs::create_directories(dir);
  // Four vertices, triangles (0 1 2) and (0 2 60000): the second one's last index is out of range.
  const std::string bad = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}], "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAAAAAAABAAIAAAACAGDq"}], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
  std::ofstream(dir / "bad.gltf") << bad;
  try {
    load_scene((dir / "bad.gltf").string());
    ADD_FAILURE() << "out-of-range indices were accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir / "bad.gltf").string() + ": faces with vertex indices out of range", 0), 0u)
        << e.what();
  }
  std::string good = bad;
  good.replace(good.find("AAIAAAACAGDq"), 12, "AAIAAAACAAMA");  // the last index 60000 -> 3
  std::ofstream(dir / "good.gltf") << good;
  EXPECT_EQ(load_scene((dir / "good.gltf").string())->description().meshes.at(0).triangles.size(), 2u);
  fs::remove_all(dir);
}

// What a glTF claims beyond the bytes it has: Assimp allocates a buffer's stated length
// before reading its file and a sparse accessor's dense array from its count alone (a fuzz
// finding: 3.4 GB for a file of 1 KB; sparse accessors are refused outright), and reads a
// .glb's binary chunk after padding the JSON chunk. Each is refused before Assimp runs,
// naming what claimed too much; the same files with honest claims load.
TEST(Tracer, GltfClaimsBeyondTheirBytesAreRefused) {
  const fs::path dir = fs::temp_directory_path() / ("fovray-claims-" + std::to_string(getpid()));
  fs::create_directories(dir);
  auto refusal = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name, std::ios::binary) << text;
    try {
      load_scene((dir / name).string());
      return std::string("loaded");
    } catch (const std::runtime_error& e) {
      const std::string what = e.what(), prefix = (dir / name).string() + ": ";
      return what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : "not named: " + what;
    }
  };
  const float corners[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
  {
    std::ofstream bin(dir / "quad.bin", std::ios::binary);
    bin.write(reinterpret_cast<const char*>(corners), sizeof corners);
    bin.write(reinterpret_cast<const char*>(indices), sizeof indices);
  }
  auto quad = [](const std::string& buffer, const std::string& uv) {
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "translation": [0, 0, -2]}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "indices": 1}]}], "buffers": [)" +
           buffer +
           R"(], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}, )" +
           uv + "]}";
  };
  const std::string buffer = R"({"byteLength": 60, "uri": "quad.bin"})";
  auto sparse_uv = [](const std::string& count) {  // zeros but for the first vertex's (0, 0)
    return R"({"componentType": 5126, "count": )" + count +
           R"(, "type": "VEC2", "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 0}}})";
  };
  // Sparse accessors, honest or not (Assimp writes where their indices point unchecked).
  const std::string sparse_refused =
      "accessor 2: sparse accessors are not supported (refused: Assimp writes where their indices point without a check)";
  EXPECT_EQ(refusal("sparse.gltf", quad(buffer, sparse_uv("4"))), sparse_refused);
  const std::string huge = quad(buffer, sparse_uv("430309376"));  // 3.4 GB dense
  EXPECT_EQ(refusal("sparse-huge.gltf", huge), sparse_refused);
  // The same claim where this loader's JSON reader and Assimp's part ways (fuzz findings):
  // ill-formed UTF-8 in a key, which Assimp's reader takes, and a key given twice, where
  // Assimp reads the first value and this reader the last. Both are refused.
  std::string bad_utf8 = huge;
  bad_utf8.replace(bad_utf8.find("componentType"), 5, std::string("co\xff\xfe") + "9");
  EXPECT_EQ(refusal("bad-utf8.gltf", bad_utf8).rfind("its JSON does not parse (refused): parse error", 0), 0u);
  std::string twice = quad(buffer, sparse_uv("430309376"));
  twice.replace(twice.rfind("\"type\": \"VEC2\""), 0, "\"count\": 4, ");
  EXPECT_EQ(refusal("twice.gltf", twice),
            "its JSON has an object with the key \"count\" twice (refused: readers differ on which counts)");
  const std::string dense_uv = R"({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC2"})";
  EXPECT_EQ(refusal("long-buffer.gltf", quad(R"({"byteLength": 2000000000, "uri": "quad.bin"})", dense_uv)),
            "buffer 0: claims 2000000000 bytes, more than the 60 bytes of " + (dir / "quad.bin").string() + " (refused)");
  EXPECT_EQ(refusal("buffer.gltf", quad(buffer, dense_uv)), "loaded");
  // A .glb whose JSON chunk is not padded to 4 bytes and whose binary chunk claims 3.4 GB.
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::string json = R"({"asset":{"version":"2.0"}}  )";
  const size_t padding = (4 - json.size() % 4) % 4;
  ASSERT_NE(padding, 0u);
  const std::string body = u32(0xCD300000u) + "BIN" + std::string(1, '\0') + std::string(8, '\0');
  const std::string glb = "glTF" + u32(2) + u32(uint32_t(20 + json.size() + padding + body.size())) +
                          u32(uint32_t(json.size())) + "JSON" + json + std::string(padding, '\0') + body;
  EXPECT_EQ(refusal("unpadded.glb", glb),
            "its binary chunk claims 3442475008 bytes, more than the " + std::to_string(glb.size()) +
                "-byte file holds (refused)");
  fs::remove_all(dir);
}

TEST(Tracer, UnreadableTexturesWarnWithTheirReason) {
  const fs::path dir = fs::temp_directory_path() / ("fovray-tex-" + std::to_string(getpid()));
  fs::create_directories(dir / "dir.png");
  std::ofstream(dir / "empty.png").close();
  std::ofstream(dir / "text.png") << "not an image\n";
  ASSERT_EQ(mkfifo((dir / "fifo.png").c_str(), 0600), 0);
  std::ofstream(dir / "quad.mtl") << "newmtl a\nKd 0.2 0.4 0.6\nmap_Kd empty.png\nmap_Ke dir.png\nmap_bump fifo.png\n"
                                     "newmtl b\nKd 1 1 1\nmap_Kd text.png\n";
  std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\nv -1 -1 -3\nv 1 -1 -3\nv 1 1 -3\nv -1 1 -3\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                     "usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 3/3 4/4\n";
  const auto s = load_scene((dir / "quad.obj").string());
  auto warned = [&](const std::string& file, const std::string& why) {
    int n = 0;
    for (const std::string& w : s->warnings()) n += w.find(file) != std::string::npos && w.find(why) != std::string::npos;
    return n;
  };
  EXPECT_EQ(warned("empty.png", "is empty (0 bytes)"), 1);
  EXPECT_EQ(warned("dir.png", "is a directory"), 1);
  EXPECT_EQ(warned("fifo.png", "not a regular file"), 1);
  EXPECT_EQ(warned("text.png", "cannot be read"), 1);
  for (const std::string& w : s->warnings()) EXPECT_EQ(w.find('\n'), std::string::npos) << "one line: " << w;
  trace_params tp;
  tp.spp = 1;
  const frame f = trace_reference(*s, look_at({0, 0, 0}, {0, 0, -1}, 60), 5, 5, tp).image;
  EXPECT_GT(f.rgb[12].b, f.rgb[12].r) << "falls back to Kd (0.2, 0.4, 0.6)";
  fs::remove_all(dir);
}

// Debian's Assimp read past the end of its buffer on "f 1 1 1/1//31/ 3//441 1" (a scene
// fuzz finding, in a file named .glb: Assimp tried its OBJ reader on it). Vertex references
// of any other form than v, v/vt, v//vn, v/vt/vn are refused before Assimp parses them,
// in .obj files and in files whose extension Assimp does not know; a .glb without its
// magic is refused as one. The four forms and comment lines still load (a '#' after a
// face is not a comment to Assimp, which refused such faces before).
TEST(Tracer, ObjFacesAssimpWouldMisreadAreRefused) {
  const fs::path dir = fs::temp_directory_path() / ("fovray-objfaces-" + std::to_string(getpid()));
  fs::create_directories(dir);
  auto message = [](const fs::path& file) {
    try {
      load_scene(file.string());
      return std::string();
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
  };
  const std::string vertices = "v -1 -1 -3\nv 1 -1 -3\nv 1 1 -3\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n";
  for (const std::string face : {"f 1 2 3", "f 1/1 2/2 3/3", "f 1//1 2//1 3//1", "f 1/1/1 2/2/1 3/3/1",
                                 "# f 1/1//31/ (a comment)\nf 1 2 3"}) {
    std::ofstream(dir / "ok.obj") << vertices << face << "\n";
    EXPECT_EQ(message(dir / "ok.obj"), "") << face;
  }
  for (const std::string face :
       {"f 1 1 1/1//31/ 3//441 1", "f 1/ 2 3", "f 1// 2 3", "f 1/1/1/ 2 3", "f a 2 3", "l 1 2/x", "f 1 2 3 # 1/1//31/"}) {
    std::ofstream(dir / "bad.obj") << vertices << face << "\n";
    const std::string why = message(dir / "bad.obj");
    EXPECT_NE(why.find("bad.obj: line 8: vertex reference"), std::string::npos) << face << ": " << why;
  }
  std::ofstream(dir / "bad.dat") << vertices << "f 1 2 3/1//\n";  // (an extension Assimp does not know)
  EXPECT_NE(message(dir / "bad.dat").find("line 8: vertex reference '3/1//'"), std::string::npos) << message(dir / "bad.dat");
  std::ofstream(dir / "obj.glb") << "f 1 1 1/1//31/ 3//441 1\n";
  EXPECT_NE(message(dir / "obj.glb").find("is not a binary glTF"), std::string::npos) << message(dir / "obj.glb");
  std::ofstream(dir / "short.glb") << "glTF";
  EXPECT_NE(message(dir / "short.glb").find("too short for a binary glTF"), std::string::npos) << message(dir / "short.glb");
  fs::remove_all(dir);
}

// env: images: special files are refused up front (/dev/zero read forever), too large an
// image is refused with its size, and NaN or infinite texels are reported and read as 0.
TEST(Tracer, EnvironmentImagesAreCheckedBeforeUse) {
  const fs::path dir = fs::temp_directory_path() / ("fovray-envcheck-" + std::to_string(getpid()));
  fs::create_directories(dir);
  auto message = [](const std::string& spec) {
    try {
      load_scene(spec);
      return std::string();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
  };
  EXPECT_NE(message("env:/dev/zero").find("not a regular file"), std::string::npos) << message("env:/dev/zero");
  EXPECT_NE(message("env:" + dir.string()).find("is a directory"), std::string::npos);
  ASSERT_EQ(mkfifo((dir / "fifo.exr").c_str(), 0600), 0);
  EXPECT_NE(message((dir / "fifo.exr").string()).find("not a regular file"), std::string::npos) << "a scene file too";
  const int w = 64, h = 32;
  std::vector<float> px(size_t(w) * h * 3, 0.5f);
  px[7] = std::numeric_limits<float>::quiet_NaN();
  px[100] = std::numeric_limits<float>::infinity();
  const std::string path = (dir / "nan.exr").string();
  auto out = OIIO::ImageOutput::create(path);
  out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
  out->write_image(OIIO::TypeDesc::FLOAT, px.data());
  out->close();
  const auto s = load_scene("env:" + path);
  ASSERT_EQ(s->warnings().size(), 1u);
  {
    // The same file rewritten at another size, read again in this process: its new pixels,
    // read at their own size (OpenImageIO's shared cache kept the old header by name, and the
    // read overflowed a buffer of the old size: the env_image fuzz target's finding).
    const std::string again = (dir / "again.hdr").string();
    auto write = [&](int iw, int ih) {  // a ramp in u: texel x holds (x + 0.5) / width
      std::vector<float> p(size_t(iw) * ih * 3);
      for (size_t i = 0; i < p.size(); ++i) p[i] = (float((i / 3) % size_t(iw)) + 0.5f) / float(iw);
      auto o = OIIO::ImageOutput::create(again);
      o->open(again, OIIO::ImageSpec(iw, ih, 3, OIIO::TypeDesc::FLOAT));
      o->write_image(OIIO::TypeDesc::FLOAT, p.data());
      o->close();
    };
    write(2, 1);
    const auto small = load_scene("env:" + again);
    write(256, 128);
    const auto large = load_scene("env:" + again);
    trace_params flat;
    flat.spp = 1;
    const frame f = trace_reference(*large, large->default_camera(90), 64, 8, flat).image;
    // Looking along -z the view spans u = 0.375 .. 0.625 (docs/tracer.md's mapping): the
    // ramp of the 256-texel image, not two texels of a stale 2 x 1 header.
    const glm::vec3 left = f.rgb[4 * 64 + 1], centre = f.rgb[4 * 64 + 32], right = f.rgb[4 * 64 + 62];
    EXPECT_NEAR(centre.g, 0.5f, 0.02f);
    EXPECT_NEAR(left.g, 0.38f, 0.02f);
    EXPECT_NEAR(right.g, 0.62f, 0.02f);
  }
  EXPECT_NE(s->warnings()[0].find("2 texel values are NaN or infinite; read as 0"), std::string::npos) << s->warnings()[0];
  trace_params tp;
  tp.spp = 4;
  const frame f = trace_reference(*s, s->default_camera(90), 32, 16, tp).image;
  for (const glm::vec3& c : f.rgb) ASSERT_TRUE(std::isfinite(c.r + c.g + c.b));
  // Two columns past the documented cap (8192 x 4096): refused from its header, before
  // its pixels are read.
  const std::string big = (dir / "big.png").string();
  auto wide = OIIO::ImageOutput::create(big);
  const int bw = 2 * max_env_height + 2, bh = max_env_height;
  wide->open(big, OIIO::ImageSpec(bw, bh, 1, OIIO::TypeDesc::UINT8));
  std::vector<uint8_t> row(size_t(bw), 0);
  for (int y = 0; y < bh; ++y) wide->write_scanline(y, 0, OIIO::TypeDesc::UINT8, row.data());
  wide->close();
  EXPECT_NE(message("env:" + big).find("larger than an environment image may be"), std::string::npos) << message("env:" + big);
  // A row far wider than any image (fewer pixels than the cap): refused from its header,
  // before OpenImageIO's scanline reading asks for gigabytes (the env_image fuzz target's
  // finding, `finding-one-row-23-million-wide.hdr`).
  const std::string row_file = (dir / "row.hdr").string();
  {
    std::ofstream o(row_file, std::ios::binary);
    o << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 1000000\n" << std::string(256, '\x80');
  }
  EXPECT_NE(message("env:" + row_file).find("is 1000000 x 1 texels, and neither side may exceed 65536"),
            std::string::npos)
      << message("env:" + row_file);
  fs::remove_all(dir);
}

TEST(Tracer, FlightHelmetReportsItsThreeMissingTextures) {
  const fs::path file = fs::path(FOV_SOURCE_DIR) / "../shared/scenes/flight-helmet/FlightHelmet.gltf";
  if (!fs::exists(file)) GTEST_SKIP() << "../shared/scenes/flight-helmet is absent";
  const auto s = load_scene(file.string());
  int missing = 0;
  for (const std::string& w : s->warnings()) missing += w.find("LeatherPartsMat") != std::string::npos;
  EXPECT_EQ(missing, 3);
  trace_params tp;
  tp.spp = 1;
  const frame f = trace_reference(*s, s->default_camera(45), 64, 64, tp).image;
  size_t hits = 0;
  for (float d : f.depth) hits += std::isfinite(d);
  EXPECT_GT(hits, 64u * 64u / 10) << "the helmet is in view";
}

TEST(Tracer, EveryAssimpSampleLoadsOrFailsCleanly) {
  const fs::path root = "/usr/share/assimp/models";
  if (!fs::exists(root)) GTEST_SKIP() << root << " is absent (package assimp-testmodels)";
  int loaded = 0, refused = 0;
  for (const char* sub : {"glTF2", "OBJ"}) {
    if (!fs::exists(root / sub)) continue;
    for (const auto& e : fs::recursive_directory_iterator(root / sub)) {
      const std::string ext = e.path().extension().string();
      if (ext != ".gltf" && ext != ".glb" && ext != ".obj") continue;
      try {
        const auto s = load_scene(e.path().string());
        trace_params tp;
        tp.spp = 1;
        const frame f = trace_reference(*s, s->default_camera(), 8, 8, tp).image;
        for (const glm::vec3& c : f.rgb) ASSERT_TRUE(std::isfinite(c.r + c.g + c.b)) << e.path();
        ++loaded;
      } catch (const std::runtime_error& err) {
        EXPECT_NE(std::string(err.what()).find(e.path().filename().string()), std::string::npos)
            << "the error names the file: " << err.what();
        ++refused;
      }
    }
  }
  EXPECT_GT(loaded, 10);
  std::cout << "assimp samples: " << loaded << " loaded, " << refused << " refused with a message\n";
}

TEST(Tracer, OneByOneAndEightKScreensWork) {
  const auto s = load_scene("builtin");
  trace_params tp;
  tp.spp = 4;
  const frame one = trace_reference(*s, s->default_camera(), 1, 1, tp).image;
  EXPECT_TRUE(std::isfinite(one.rgb[0].r));
  tp.spp = 1;
  const frame big = trace_reference(*s, s->default_camera(), 7680, 4320, tp).image;
  EXPECT_EQ(big.rgb.size(), 7680u * 4320u);
  size_t finite = 0;
  for (const glm::vec3& c : big.rgb) finite += std::isfinite(c.r + c.g + c.b) && c.r >= 0;
  EXPECT_EQ(finite, big.rgb.size());
  EXPECT_THROW(trace_reference(*s, s->default_camera(), 0, 10, tp).image, std::invalid_argument);
  tp.spp = 0;
  EXPECT_THROW(trace_reference(*s, s->default_camera(), 10, 10, tp).image, std::invalid_argument);
}

// A glTF file with one square of side 2 (four corners, counter-clockwise) and the given
// nodes and camera (JSON), its buffer inline.
std::string write_gltf(const std::string& name, const float corners[12], const std::string& nodes,
                       const std::string& camera) {
  std::string bytes(reinterpret_cast<const char*>(corners), 48);
  const uint16_t index[8] = {0, 1, 2, 0, 2, 3, 0, 0};
  bytes.append(reinterpret_cast<const char*>(index), 16);
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const size_t length = bytes.size(), padding = (3 - length % 3) % 3;
  bytes.append(padding, '\0');
  std::string b64;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
    for (int k = 3; k >= 0; --k) b64 += digits[(v >> (6 * k)) & 63];
  }
  b64.replace(b64.size() - padding, padding, padding, '=');
  float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
  for (int c = 0; c < 12; ++c) lo[c % 3] = std::min(lo[c % 3], corners[c]), hi[c % 3] = std::max(hi[c % 3], corners[c]);
  const fs::path file = fs::path(::testing::TempDir()) / name;
  std::ofstream(file) << "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0},"
                      << nodes << "],\"cameras\":[" << camera
                      << "],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
                         "\"buffers\":[{\"byteLength\":64,\"uri\":\"data:application/octet-stream;base64,"
                      << b64
                      << "\"}],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
                         "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":12}],\"accessors\":[{\"bufferView\":0,"
                         "\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":["
                      << lo[0] << "," << lo[1] << "," << lo[2] << "],\"max\":[" << hi[0] << "," << hi[1] << "," << hi[2]
                      << "]},{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]}";
  return file.string();
}

// The run of pixels along a row (or a column) that hit geometry.
int hit_run(const frame& f, bool row) {
  int n = 0;
  for (int i = 0; i < (row ? f.width : f.height); ++i) {
    const size_t at = row ? size_t(f.height / 2) * f.width + i : size_t(i) * f.width + f.width / 2;
    n += std::isfinite(f.depth[at]);
  }
  return n;
}

// glTF cameras: placed by their node once (Assimp's glTF importer also copies the node's
// translation into the camera), with the vertical field of view the file stores (Assimp
// keeps yfov x aspect); checked against the pinhole projection of a known square.
TEST(Tracer, GltfCamerasArePlacedOnceWithTheirStoredFieldOfView) {
  const float facing_z[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const std::string ahead = write_gltf("camera-ahead.gltf", facing_z, "{\"camera\":0,\"translation\":[0,0,4]}",
                                       "{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,\"aspectRatio\":1.5,\"znear\":0.1}}");
  const auto s = load_scene(ahead);
  ASSERT_TRUE(s->description().scene_camera);
  const camera cam = setup_camera(*s);
  EXPECT_NEAR(glm::distance(cam.position, glm::vec3(0, 0, 4)), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::distance(cam.forward, glm::vec3(0, 0, -1)), 0.0f, 1e-5f);
  EXPECT_NEAR(cam.vfov_deg, glm::degrees(0.8f), 1e-4f);
  trace_params tp;
  tp.spp = 1;
  tp.shadows = false;
  // At the file's aspect the square is 2 / (2 * 4 * tan(0.4)) of the height, in both directions.
  const double expected = 200 * 2 / (8 * std::tan(0.4));
  const frame wide = trace_reference(*s, cam, 300, 200, tp).image;
  EXPECT_NEAR(hit_run(wide, true), expected, 0.02 * expected);
  EXPECT_NEAR(hit_run(wide, false), expected, 0.02 * expected);
  // Another aspect keeps the vertical field of view, as glTF says.
  const frame square = trace_reference(*s, cam, 200, 200, tp).image;
  EXPECT_NEAR(hit_run(square, false), expected, 0.02 * expected);
  EXPECT_NEAR(hit_run(square, true), expected, 0.02 * expected);
  // --hfov replaces the file's field of view.
  camera_overrides o;
  o.hfov_deg = 60;
  const frame sixty = trace_reference(*s, setup_camera(*s, o), 300, 200, tp).image;
  const double at_sixty = 300 * 2 / (8 * std::tan(glm::radians(30.0)));
  EXPECT_NEAR(hit_run(sixty, true), at_sixty, 0.02 * at_sixty);

  // A camera that looks sideways (+90 degrees about y: along -x), in a translated parent.
  const float facing_x[12] = {0, -1, 1, 0, -1, -1, 0, 1, -1, 0, 1, 1};
  const std::string side = write_gltf(
      "camera-side.gltf", facing_x,
      "{\"translation\":[2,0,0],\"children\":[2]},{\"camera\":0,\"translation\":[3,0,0],\"rotation\":[0,0.70710678,0,0.70710678]}",
      "{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,\"znear\":0.1}}");
  const auto t = load_scene(side);
  const camera sc = setup_camera(*t);
  EXPECT_NEAR(glm::distance(sc.position, glm::vec3(5, 0, 0)), 0.0f, 1e-4f);
  EXPECT_NEAR(glm::distance(sc.forward, glm::vec3(-1, 0, 0)), 0.0f, 1e-4f);
  const frame f = trace_reference(*t, sc, 400, 400, tp).image;
  const double at_five = 400 * 2 / (10 * std::tan(0.4));
  EXPECT_NEAR(hit_run(f, true), at_five, 0.02 * at_five);
  EXPECT_NEAR(hit_run(f, false), at_five, 0.02 * at_five);
}

// Eye, target and up overrides, for a scene with its own camera.
TEST(Tracer, CameraOverridesPlaceAndAimTheCamera) {
  const auto s = load_scene("builtin");
  camera_overrides o;
  o.eye = glm::vec3(1, 2, 3);
  const camera moved = setup_camera(*s, o);
  EXPECT_EQ(moved.position, glm::vec3(1, 2, 3));
  EXPECT_EQ(moved.forward, setup_camera(*s).forward);  // an eye alone keeps the direction
  o.target = glm::vec3(1, 2, -7);
  const camera aimed = setup_camera(*s, o);
  EXPECT_NEAR(glm::distance(aimed.forward, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
  o.up = glm::vec3(0, 1, 0);
  EXPECT_NO_THROW(setup_camera(*s, o));
  o.up = glm::vec3(0, 0, 1);  // parallel to the view
  EXPECT_THROW(setup_camera(*s, o), usage_error);
  o.up.reset();
  o.target = o.eye;
  EXPECT_NE(validate(o), "");
  EXPECT_THROW(setup_camera(*s, o), usage_error);
  o.target.reset();
  o.eye = glm::vec3(NAN, 0, 0);
  EXPECT_NE(validate(o), "");
}

// A glTF file of one quad facing +z seen by its camera 4 units away, and a file's text.
std::string write_quad_gltf(const std::string& name) {
  const float facing_z[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  return write_gltf(name, facing_z, "{\"camera\":0,\"translation\":[0,0,4]}",
                    "{\"type\":\"perspective\",\"perspective\":{\"yfov\":1,\"znear\":0.1}}");
}
std::string read_text(const std::string& file) {
  std::ifstream in(file);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Extensions a glTF file declares that fovray does not implement are warned about once
// each, naming the file and the extension (material extensions saying how the material
// shades instead); KHR_lights_punctual, which fovray reads, is not; past 16 the rest are
// counted. The file still loads.
TEST(Tracer, UnsupportedGltfExtensionsWarnOnceEach) {
  const std::string plain = write_quad_gltf("extensions-plain.gltf");
  const std::string json = read_text(plain);
  auto with = [&](const std::string& name, const std::string& used) {
    const std::string file = (fs::path(::testing::TempDir()) / name).string();
    std::ofstream(file) << "{\"extensionsUsed\":[" << used << "]," << json.substr(1);
    return file;
  };
  auto count = [](const std::vector<std::string>& warnings, const std::string& part) {
    return std::count_if(warnings.begin(), warnings.end(), [&](const std::string& w) { return w.find(part) != std::string::npos; });
  };
  const std::string some = with("extensions-some.gltf", R"("KHR_materials_clearcoat","KHR_lights_punctual","EXT_other","KHR_materials_clearcoat",7)");
  const auto s = load_scene(some);
  EXPECT_EQ(count(s->warnings(), some + ": uses the glTF extension KHR_materials_clearcoat, which fovray does not support: "
                                        "ignored (its materials shade by the core metallic-roughness model)"), 1);
  EXPECT_EQ(count(s->warnings(), some + ": uses the glTF extension EXT_other, which fovray does not support: ignored"), 1);
  EXPECT_EQ(count(s->warnings(), "extension 7,"), 1);  // not a string: named as its JSON
  EXPECT_EQ(count(s->warnings(), "KHR_lights_punctual"), 0);
  EXPECT_EQ(s->warnings().size(), 3u);
  EXPECT_TRUE(load_scene(plain)->warnings().empty());
  std::string many;
  for (int i = 0; i < 20; ++i) many += fmt::format("{}\"EXT_{}\"", i ? "," : "", i);
  const auto m = load_scene(with("extensions-many.gltf", many));
  EXPECT_EQ(count(m->warnings(), "uses the glTF extension EXT_"), 16);
  EXPECT_EQ(count(m->warnings(), "uses 4 more glTF extensions fovray does not support: ignored"), 1);
}

// KHR_materials_emissive_strength: a material's emission is its emissive factor times the
// strength, with no warning about the extension; a strength out of range refuses the file,
// naming it and the material.
TEST(Tracer, EmissiveStrengthScalesTheEmission) {
  const std::string json = read_text(write_quad_gltf("emissive-plain.gltf"));
  auto with_strength = [&](const std::string& name, const std::string& strength) {
    std::string text = json;
    const std::string primitive = "\"indices\":1}";
    text.replace(text.find(primitive), primitive.size(), "\"indices\":1,\"material\":0}");
    const std::string file = (fs::path(::testing::TempDir()) / name).string();
    std::ofstream(file) << "{\"extensionsUsed\":[\"KHR_materials_emissive_strength\"],\"materials\":[{\"name\":\"lamp\","
                           "\"emissiveFactor\":[0.5,0.25,1],\"extensions\":{\"KHR_materials_emissive_strength\":"
                           "{\"emissiveStrength\":"
                        << strength << "}}}]," << text.substr(1);
    return file;
  };
  auto lamp = [](const scene& sc) {
    for (const material& m : sc.description().materials)
      if (m.name == "lamp") return m;
    ADD_FAILURE() << "no material 'lamp'";
    return material();
  };
  const auto s = load_scene(with_strength("emissive-4.gltf", "4"));
  EXPECT_EQ(lamp(*s).emissive, glm::vec3(2, 1, 4));
  EXPECT_TRUE(s->warnings().empty()) << s->warnings().front();
  // Through the tracer: the quad (facing the camera, lit by the default sun as well) shows
  // three times its emissive factor more at strength 4 than at strength 1.
  const auto one = load_scene(with_strength("emissive-1.gltf", "1"));
  EXPECT_EQ(lamp(*one).emissive, glm::vec3(0.5f, 0.25f, 1));
  trace_params tp;
  tp.spp = 1;
  tp.method = integrator::path, tp.bounces = 0;
  const frame bright = trace_reference(*s, s->default_camera(60), 16, 16, tp).image;
  const frame dim = trace_reference(*one, one->default_camera(60), 16, 16, tp).image;
  const size_t centre = 8 * 16 + 8;
  EXPECT_NEAR(bright.rgb[centre].b - dim.rgb[centre].b, 3.0f, 1e-5f);
  EXPECT_NEAR(bright.rgb[centre].r - dim.rgb[centre].r, 1.5f, 1e-5f);
  for (const char* bad : {"-1", "1e7", "\"4\"", "null"}) {
    const std::string file = with_strength("emissive-bad.gltf", bad);
    try {
      load_scene(file);
      ADD_FAILURE() << bad;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(file + ": material 0 'lamp': emissiveStrength"), std::string::npos) << e.what();
    }
  }
}

// glTF alpha modes are read as the file gives them: OPAQUE, MASK with its cutoff, BLEND.
TEST(Tracer, GltfAlphaModesAreRead) {
  const float facing_z[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const std::string plain = write_gltf("alpha-plain.gltf", facing_z, "{\"camera\":0,\"translation\":[0,0,4]}",
                                       "{\"type\":\"perspective\",\"perspective\":{\"yfov\":1,\"znear\":0.1}}");
  std::ifstream in(plain);
  const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [mode, expected] : {std::pair<std::string, alpha_mode>{"OPAQUE", alpha_mode::opaque},
                                       {"MASK", alpha_mode::mask}, {"BLEND", alpha_mode::blend}}) {
    std::string text = json;
    const std::string primitive = "\"indices\":1}";
    text.replace(text.find(primitive), primitive.size(), "\"indices\":1,\"material\":0}");
    const std::string file = (fs::path(::testing::TempDir()) / ("alpha-" + mode + ".gltf")).string();
    std::ofstream(file) << "{\"materials\":[{\"name\":\"glass\",\"alphaMode\":\"" << mode
                        << "\",\"alphaCutoff\":0.3}]," << text.substr(1);
    const auto sc = load_scene(file);
    bool found = false;
    for (const material& m : sc->description().materials)
      if (m.name == "glass") {
        found = true;
        EXPECT_EQ(m.alpha, expected) << mode;
        if (expected == alpha_mode::mask) {
          EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
        }
      }
    EXPECT_TRUE(found) << mode;
  }
}

}  // namespace
}  // namespace fov
