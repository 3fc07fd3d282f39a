// The interactive tools' frame pipeline: tracing the next frame ahead (begin_trace) must
// give exactly the frame tracing it in turn gives, and never a stale one.
#include <gtest/gtest.h>

#include "fov/dart_throwing.h"
#include "fov/knn_table.h"
#include "live_renderer.h"

namespace fov {
namespace {

std::shared_ptr<const pointset> small_set() {
  auto set = std::make_shared<pointset>();
  set->model.display = {64, 48, 1.0};
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

struct pipeline : ::testing::Test {
  std::shared_ptr<const scene> scn = load_scene("builtin");
  std::shared_ptr<const pointset> set = small_set();
  live_settings settings;
  void SetUp() override {
    settings.spp = 2;
    settings.taa = false;  // a fixed ray pattern: each frame depends on gaze and camera only
    settings.reconstruct.k = 5;
  }
};

TEST_F(pipeline, TracingAheadGivesTheSameFrame) {
  live_renderer in_turn(scn, scn->default_camera(90)), ahead(scn, scn->default_camera(90));
  in_turn.use_pointset(set);
  ahead.use_pointset(set);
  const double gaze[3][2] = {{32, 24}, {10, 40}, {60, 5}};
  for (const auto& g : gaze) {
    live_timing t;
    ahead.begin_trace(g[0], g[1], ahead.cam(), settings);
    const frame b = ahead.foveated(g[0], g[1], settings, &t);
    EXPECT_TRUE(t.traced_ahead);
    const frame a = in_turn.foveated(g[0], g[1], settings);
    EXPECT_EQ(max_difference(a, b), 0.0f) << "gaze " << g[0] << ", " << g[1];
  }
}

TEST_F(pipeline, AStaleTraceIsDroppedNotShown) {
  live_renderer in_turn(scn, scn->default_camera(90)), ahead(scn, scn->default_camera(90));
  in_turn.use_pointset(set);
  ahead.use_pointset(set);
  live_timing t;
  // Traced ahead for another gaze: the frame must be the one for the gaze asked for.
  ahead.begin_trace(5, 5, ahead.cam(), settings);
  frame b = ahead.foveated(50, 30, settings, &t);
  EXPECT_FALSE(t.traced_ahead);
  EXPECT_EQ(max_difference(in_turn.foveated(50, 30, settings), b), 0.0f);
  // ... for another camera (the view moved after the trace began).
  camera moved = ahead.cam();
  moved.position += glm::vec3(0.5f, 0, 0);
  ahead.begin_trace(50, 30, ahead.cam(), settings);
  ahead.cam() = moved;
  in_turn.cam() = moved;
  b = ahead.foveated(50, 30, settings, &t);
  EXPECT_FALSE(t.traced_ahead);
  const frame a = in_turn.foveated(50, 30, settings);
  EXPECT_EQ(max_difference(a, b), 0.0f);
  // ... for other rays per point, and another k (another set of traced points).
  live_settings more = settings;
  more.spp = 3;
  ahead.begin_trace(50, 30, ahead.cam(), settings);
  b = ahead.foveated(50, 30, more, &t);
  EXPECT_FALSE(t.traced_ahead);
  EXPECT_EQ(max_difference(in_turn.foveated(50, 30, more), b), 0.0f);
  more = settings;
  more.reconstruct.k = 8;
  ahead.begin_trace(50, 30, ahead.cam(), settings);
  b = ahead.foveated(50, 30, more, &t);
  EXPECT_FALSE(t.traced_ahead);
  EXPECT_EQ(max_difference(in_turn.foveated(50, 30, more), b), 0.0f);
  // The frames differ at all between these cases (else the checks above prove nothing).
  const frame near_corner = in_turn.foveated(5, 5, settings);  // a copy: foveated() reuses its frame
  EXPECT_GT(max_difference(near_corner, in_turn.foveated(50, 30, settings)), 0.01f);
}

TEST_F(pipeline, WithoutTaaTheRayPatternStaysFixed) {
  live_renderer r(scn, scn->default_camera(90));
  r.use_pointset(set);
  const frame a = r.foveated(32, 24, settings);
  const frame b = r.foveated(32, 24, settings);
  EXPECT_EQ(max_difference(a, b), 0.0f);
  EXPECT_GT(max_difference(a, r.foveated(40, 20, settings)), 0.01f);  // and the comparison can fail
}

}  // namespace
}  // namespace fov
