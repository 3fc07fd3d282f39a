// The integrators (trace_params::method): known answers in furnaces, emission only where a
// material emits, the direct integrator's Lambert shading unchanged by the path integrator's
// shared parts, and the determinism of bounces.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "fov/scene.h"
#include "fov/trace.h"

using namespace fov;

namespace {

constexpr float pi = 3.14159265358979f;

// A sphere of flat triangles (no vertex normals: the shading normal is the geometric one).
mesh sphere(glm::vec3 centre, float radius, uint32_t material, int rings = 24, int segments = 48) {
  mesh m;
  m.material = material;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const float theta = pi * float(r) / float(rings), phi = 2 * pi * float(s) / float(segments);
      m.positions.push_back(centre + radius * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                          std::sin(theta) * std::sin(phi)));
    }
  const uint32_t w = uint32_t(segments + 1);
  for (uint32_t r = 0; r < uint32_t(rings); ++r)
    for (uint32_t s = 0; s < uint32_t(segments); ++s) {
      const uint32_t a = r * w + s, b = a + w;
      if (r > 0) m.triangles.push_back({a, a + 1, b});
      if (r + 1 < uint32_t(rings)) m.triangles.push_back({a + 1, b + 1, b});
    }
  return m;
}

mesh ground(float y, float half, uint32_t material) {
  mesh m;
  m.material = material;
  m.positions = {{-half, y, -half}, {half, y, -half}, {half, y, half}, {-half, y, half}};
  m.triangles = {{0, 2, 1}, {0, 3, 2}};
  return m;
}

// One sphere of `mat` at the origin (and a ground of the same material below it, when
// asked) in a uniform environment of radiance `env`, with no light.
scene_description furnace(material mat, float env, bool with_ground = false) {
  scene_description d;
  d.materials.push_back(mat);
  d.meshes.push_back(sphere({0, 0, 0}, 1, 0));
  d.instances.push_back({0, glm::mat4(1.0f), ""});
  if (with_ground) {
    d.meshes.push_back(ground(-1, 50, 0));
    d.instances.push_back({1, glm::mat4(1.0f), ""});
  }
  d.sun.colour = glm::vec3(0);
  d.env.colour = glm::vec3(env);
  return d;
}

material lambert(float albedo) {
  material m;
  m.base_colour = glm::vec4(glm::vec3(albedo), 1);
  return m;
}
material metal(float roughness) {
  material m;
  m.model = shading_model::metallic_roughness;
  m.base_colour = glm::vec4(1);
  m.metallic = 1, m.roughness = roughness;
  return m;
}

// The mean green value of the pixels that see the sphere (depth finite, within the disc
// the sphere covers from the camera at distance 3).
struct pixel_mean {
  double mean = 0;
  size_t pixels = 0;
};
pixel_mean sphere_mean(const scene& s, const trace_params& tp, int size = 48) {
  const frame f = trace_reference(s, look_at({0, 0, 3}, {0, 0, 0}, 50), size, size, tp).image;
  pixel_mean m;
  for (size_t i = 0; i < f.rgb.size(); ++i) {
    const int x = int(i % size), y = int(i / size);
    const float dx = float(x) + 0.5f - size / 2.0f, dy = float(y) + 0.5f - size / 2.0f;
    if (!std::isfinite(f.depth[i]) || std::hypot(dx, dy) > 0.3f * size) continue;  // the sphere's inner disc
    m.mean += f.rgb[i].g, ++m.pixels;
  }
  m.mean /= double(std::max<size_t>(1, m.pixels));
  return m;
}

trace_params path(uint32_t bounces, uint32_t spp = 4) {
  trace_params tp;
  tp.method = integrator::path;
  tp.bounces = bounces;
  tp.spp = spp;
  return tp;
}

}  // namespace

// The white furnace: a white Lambertian sphere in a uniform white environment. Every ray
// leaving a convex object escapes, so one bounce already returns the environment's radiance
// exactly (each cosine-weighted bounce carries the albedo, 1); no bounce returns nothing (the
// path integrator has no ambient term).
TEST(Integrator, AWhiteSphereInAWhiteFurnaceReturnsTheEnvironment) {
  const scene s(furnace(lambert(1), 1));
  EXPECT_EQ(sphere_mean(s, path(0)).mean, 0.0);
  for (uint32_t bounces : {1u, 2u, 5u}) {
    const pixel_mean m = sphere_mean(s, path(bounces));
    ASSERT_GT(m.pixels, 500u);
    EXPECT_NEAR(m.mean, 1.0, 1e-5) << bounces << " bounces";
  }
  // A grey one returns its albedo.
  const scene grey(furnace(lambert(0.5f), 1));
  EXPECT_NEAR(sphere_mean(grey, path(3)).mean, 0.5, 1e-5);
}

// With a white ground below it, light reaches the sphere after several bounces between the
// two: each bounce adds some, never past the environment's radiance, and many bounces come
// close to it (Russian roulette keeps the estimate unbiased).
TEST(Integrator, MoreBouncesApproachTheFurnaceFromBelow) {
  const scene s(furnace(lambert(1), 1, true));
  double previous = 0;
  for (uint32_t bounces : {1u, 2u, 4u, 32u}) {
    const pixel_mean m = sphere_mean(s, path(bounces, 16));
    EXPECT_GT(m.mean, previous) << bounces << " bounces";
    EXPECT_LE(m.mean, 1.0 + 0.01) << bounces << " bounces";
    std::printf("white sphere on a white ground, %u bounces: %.4f\n", bounces, m.mean);
    previous = m.mean;
  }
  EXPECT_GT(previous, 0.97) << "32 bounces";
}

// The weak furnace through the integrator: a white rough metal absorbs nothing and never
// returns more than the environment sends, at every roughness.
TEST(Integrator, AWhiteMetalSphereNeverReturnsMoreThanArrives) {
  for (float roughness : {0.05f, 0.3f, 0.6f, 1.0f}) {
    const scene s(furnace(metal(roughness), 1));
    const pixel_mean m = sphere_mean(s, path(1, 16));
    EXPECT_LE(m.mean, 1.0 + 0.01) << "roughness " << roughness;
    EXPECT_GT(m.mean, 0.3) << "roughness " << roughness;
    std::printf("white metal sphere, roughness %.2f: %.4f\n", roughness, m.mean);
  }
}

// In the dark, nothing but an emissive material gives light: a non-emissive sphere is black
// under both integrators at any depth, an emissive one shows its emission.
TEST(Integrator, EmissionComesOnlyFromEmissiveMaterials) {
  const scene dark(furnace(lambert(0.8f), 0));
  EXPECT_EQ(sphere_mean(dark, path(3)).mean, 0.0);
  trace_params direct;
  direct.spp = 4;
  EXPECT_EQ(sphere_mean(dark, direct).mean, 0.0);
  material glowing = lambert(0.8f);
  glowing.emissive = glm::vec3(0.25f);
  const scene lit(furnace(glowing, 0));
  EXPECT_NEAR(sphere_mean(lit, path(3)).mean, 0.25, 1e-6);
  EXPECT_NEAR(sphere_mean(lit, direct).mean, 0.25, 1e-6);
}

// The path integrator at 0 bounces is the direct integrator without its ambient term, bit
// for bit: the same first hit, light and shadow ray (Lambert and metallic-roughness).
TEST(Integrator, PathWithoutBouncesIsDirectWithoutAmbient) {
  for (const material& m : {lambert(0.7f), metal(0.4f)}) {
    scene_description d = furnace(m, 0.6f, true);
    d.sun.colour = glm::vec3(0.9f, 0.8f, 0.7f);
    d.env.ambient = 0;
    const scene s(d);
    trace_params direct;
    direct.spp = 2;
    const frame a = trace_reference(s, look_at({0, 0.5f, 3}, {0, -0.3f, 0}, 70), 40, 30, direct).image;
    const frame b = trace_reference(s, look_at({0, 0.5f, 3}, {0, -0.3f, 0}, 70), 40, 30, path(0, 2)).image;
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i]) << i;
  }
}

// Bounces draw their random numbers from the seed and the ray: the same frame twice is
// the same bit for bit (whatever thread traced a tile), another seed differs.
TEST(Integrator, BouncesAreDeterministic) {
  const scene s(furnace(lambert(0.8f), 1, true));
  const frame a = trace_reference(s, look_at({0, 0, 3}, {0, 0, 0}, 50), 32, 32, path(3)).image;
  const frame b = trace_reference(s, look_at({0, 0, 3}, {0, 0, 0}, 50), 32, 32, path(3)).image;
  trace_params other = path(3);
  other.seed = 2;
  const frame c = trace_reference(s, look_at({0, 0, 3}, {0, 0, 0}, 50), 32, 32, other).image;
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_NE(a.rgb, c.rgb);
}
