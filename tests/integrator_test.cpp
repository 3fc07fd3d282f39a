// The integrators (trace_params::method): known answers in furnaces, emission only where a
// material emits, the direct integrator's Lambert shading unchanged by the path integrator's
// shared parts, and the determinism of bounces.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

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
  d.lights.at(0).colour = glm::vec3(0);
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
    d.lights.at(0).colour = glm::vec3(0.9f, 0.8f, 0.7f);
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

// Every ray is counted by kind, and recorded when asked as it was cast. A white sphere lit
// from the camera's side: every visible point faces the light, so the direct integrator casts
// one shadow ray per hit; a bounce from a convex object always escapes, so one bounce adds
// one bounce ray per hit and no further vertex (hence no further shadow ray).
TEST(Integrator, CountsAndRecordsEveryRayItCasts) {
  scene_description d = furnace(lambert(1), 1);
  d.lights.at(0).colour = glm::vec3(0.5f);
  d.lights.at(0).direction = glm::vec3(0, 0, 1);
  const scene s(d);
  const int size = 40;
  const camera cam = look_at({0, 0, 3}, {0, 0, 0}, 50);
  for (uint32_t bounces : {0u, 1u}) {
    trace_params tp = path(bounces, 1);
    if (bounces == 0) tp.method = integrator::direct;
    tp.record_rays = true;
    const reference_trace r = trace_reference(s, cam, size, size, tp);
    uint64_t hits = 0;
    for (float z : r.image.depth) hits += std::isfinite(z) ? 1 : 0;
    ASSERT_GT(hits, 300u);
    ASSERT_LT(hits, uint64_t(size * size));
    const ray_counts& c = r.stats.cast;
    EXPECT_EQ(c.primary, uint64_t(size * size));
    EXPECT_EQ(c.primary, r.image.rays);
    EXPECT_EQ(c.shadow, hits) << bounces << " bounces";
    EXPECT_EQ(c.bounce, bounces * hits);
    ray_counts recorded;
    uint64_t packets = 0;
    for (const std::vector<recorded_ray>& task : r.stats.recorded)
      for (const recorded_ray& ray : task) {
        EXPECT_NEAR(glm::length(ray.dir), 1.0f, 1e-5f);
        if (ray.how == recorded_ray::kind::primary) {
          ++recorded.primary, packets += ray.starts_packet ? 1 : 0;
          EXPECT_EQ(ray.origin, glm::vec3(0, 0, 3));
        } else if (ray.how == recorded_ray::kind::bounce) {
          ++recorded.bounce;
          // Leaves the sphere's surface (flat facets lie up to 1 % inside the unit sphere).
          EXPECT_NEAR(glm::length(ray.origin), 0.995f, 6e-3f);
        } else {
          ++recorded.shadow;
          EXPECT_EQ(ray.how, recorded_ray::kind::packet_shadow);  // only first hits meet the light
          EXPECT_EQ(ray.dir, glm::vec3(0, 0, 1));
          EXPECT_EQ(ray.tfar, std::numeric_limits<float>::infinity());
        }
      }
    EXPECT_EQ(recorded.primary, c.primary);
    EXPECT_EQ(recorded.shadow, c.shadow);
    EXPECT_EQ(recorded.bounce, c.bounce);
    EXPECT_EQ(packets, uint64_t(size * size / 16));  // 8x8-pixel tiles: four full packets each
    // Without recording, the same counts and nothing kept.
    tp.record_rays = false;
    const reference_trace plain = trace_reference(s, cam, size, size, tp);
    EXPECT_EQ(plain.stats.cast.total(), c.total());
    EXPECT_TRUE(plain.stats.recorded.empty());
  }
}

// A spot light lights what lies within its cone: fully within the inner angle (its
// intensity over the squared distance, times the cosine), nothing beyond the outer one.
// A spot 2 units above a white ground, pointing down, seen from straight above.
TEST(Lights, ASpotLightsItsConeAndNothingBeyond) {
  scene_description d;
  d.materials.push_back(lambert(1));
  d.meshes.push_back(ground(0, 20, 0));
  d.instances.push_back({0, glm::mat4(1.0f), ""});
  light spot;
  spot.type = light::kind::spot;
  spot.position = {0, 2, 0};
  spot.axis = {0, -1, 0};
  spot.inner_cone = 0.3f, spot.outer_cone = 0.5f;
  spot.colour = glm::vec3(4);
  d.lights = {spot};
  d.env.colour = glm::vec3(0);
  const scene s(d);
  const int size = 200;
  const camera cam = look_at({0, 10, 0}, {0, 0, 0}, 40, {0, 0, -1});
  trace_params tp;
  tp.spp = 1;
  const frame f = trace_reference(s, cam, size, size, tp).image;
  const camera_frame cf = make_frame(cam, size, size);
  int inside = 0, outside = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      // Where the pixel's centre meets the ground, and its angle from the spot's axis.
      const glm::vec3 dir = ray_direction(cf, float(x) + 0.5f, float(y) + 0.5f);
      const glm::vec3 p = cf.origin + dir * (cf.origin.y / -dir.y);
      const float r = std::hypot(p.x, p.z), angle = std::atan2(r, 2.0f);
      const float value = f.rgb[size_t(y) * size + x].g;
      if (angle < spot.inner_cone - 0.02f) {  // (a pixel spans about 0.01 rad here)
        const float d2 = r * r + 4, cosine = 2 / std::sqrt(d2);
        EXPECT_NEAR(value, 4 * cosine / d2, 0.02f * 4 * cosine / d2) << x << "," << y;
        ++inside;
      } else if (angle > spot.outer_cone + 0.02f) {
        EXPECT_EQ(value, 0.0f) << x << "," << y;
        ++outside;
      }
    }
  EXPECT_GT(inside, 600);
  EXPECT_GT(outside, 1000);
}

// Every light lights the scene: two lights give the sum of what each gives alone (the
// ambient term counted once), within float rounding.
TEST(Lights, EveryLightAdds) {
  scene_description d = furnace(lambert(0.8f), 0.5f, true);
  light a, b;
  a.direction = glm::normalize(glm::vec3(1, 1, 0.5f)), a.colour = {0.5f, 0.4f, 0.3f};
  b.type = light::kind::point, b.position = {-2, 3, 2}, b.colour = {2, 3, 4};
  const camera cam = look_at({0, 1, 4}, {0, -0.5f, 0}, 60);
  trace_params tp;
  tp.spp = 2;
  auto render = [&](std::vector<light> lights, float ambient) {
    d.lights = std::move(lights);
    d.env.ambient = ambient;
    const scene s(d);
    return trace_reference(s, cam, 48, 36, tp).image;
  };
  const frame both = render({a, b}, 0.35f), only_a = render({a}, 0.35f), only_b = render({b}, 0), none = render({}, 0);
  int lit_by_b = 0;
  size_t edge = 0;
  for (size_t i = 0; i < both.rgb.size(); ++i) {
    // Pixels all of whose rays hit: unlit, they are black (where some rays see the
    // environment, it would be counted twice in the sum).
    if (!std::isfinite(both.depth[i])) continue;
    if (none.rgb[i] != glm::vec3(0)) {
      ++edge;
      continue;
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(both.rgb[i][c], only_a.rgb[i][c] + only_b.rgb[i][c], 1e-5f) << i;
    lit_by_b += only_b.rgb[i].g > 0;
  }
  EXPECT_LT(edge, both.rgb.size() / 10);
  EXPECT_GT(lit_by_b, 100);
}

// A glTF file's KHR_lights_punctual lights, every one: placed by their nodes (a spot shines
// along its node's -Z), cone half-angles as the file gives them, glTF's intensity times
// colour divided by pi (fovray's light colour is what a white Lambertian surface facing
// the light shows); a light with a non-finite value refuses the file, naming it.
TEST(Lights, GltfPunctualLightsAreReadEveryOne) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "lights";
  std::filesystem::create_directories(dir);
  auto file = [&](const std::string& name, const std::string& intensity) {
    const std::string text =
        R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"], "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "color": [1, 0.5, 0.25], "intensity": 3.14159265}, {"type": "spot", "color": [1, 1, 1], "intensity": )" +
        intensity +
        R"(, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}]}}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}], "nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}}, {"translation": [1, 2, 3], "rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 1}}}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}], "bufferViews": [{"buffer": 0, "byteLength": 36}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]})";
    std::ofstream((dir / name).string()) << text;
    return (dir / name).string();
  };
  const std::unique_ptr<scene> s = load_scene(file("lights.gltf", "6.28318531"));
  const std::vector<light>& lights = s->description().lights;
  ASSERT_EQ(lights.size(), 2u);
  EXPECT_EQ(lights[0].type, light::kind::directional);
  EXPECT_NEAR(lights[0].colour.r, 1, 1e-5f);
  EXPECT_NEAR(lights[0].colour.b, 0.25f, 1e-5f);
  EXPECT_NEAR(lights[0].direction.z, 1, 1e-5f) << "a directional light shines along its node's -Z: towards it is +Z";
  const light& spot = lights[1];
  EXPECT_EQ(spot.type, light::kind::spot);
  EXPECT_NEAR(spot.colour.g, 2, 1e-5f);
  EXPECT_NEAR(spot.inner_cone, 0.2f, 1e-5f);
  EXPECT_NEAR(spot.outer_cone, 0.6f, 1e-5f);
  EXPECT_NEAR(glm::distance(spot.position, glm::vec3(1, 2, 3)), 0, 1e-5f);
  EXPECT_NEAR(glm::distance(spot.axis, glm::vec3(0, -1, 0)), 0, 1e-4f) << "-Z turned -90 degrees about X: down";
  const std::string bad = file("bad-light.gltf", "1e39");
  try {
    load_scene(bad);
    ADD_FAILURE() << "an infinite intensity was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(bad + ": light '", 0), 0u) << e.what();
  }
}

namespace {

// A lat-long EXR of w x h texels, colour(s, t) at each texel centre (s, t in [0, 1]).
template <class F>
std::string write_env(const std::string& name, int w, int h, F&& colour) {
  std::vector<float> px(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 c = colour((float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h));
      for (int k = 0; k < 3; ++k) px[(size_t(y) * w + x) * 3 + k] = c[k];
    }
  const std::string file = (std::filesystem::path(::testing::TempDir()) / name).string();
  auto out = OIIO::ImageOutput::create(file);
  out->open(file, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
  out->write_image(OIIO::TypeDesc::FLOAT, px.data());
  out->close();
  return file;
}

// A sky (brighter towards the top) with a small, bright sun: the case BRDF sampling alone
// finds noisy.
std::string sky_with_sun() {
  return write_env("sky.exr", 256, 128, [](float s, float t) {
    const bool sun = std::hypot(s - 0.42f, t - 0.3f) < 0.02f;
    return sun ? glm::vec3(400, 380, 350) : glm::vec3(0.3f, 0.4f, 0.6f) * (1.2f - t);
  });
}

}  // namespace

// Sampling the environment image as a light (by luminance, with MIS) changes the noise,
// not the answer: a grey sphere on a ground under a sky with a small sun has the same mean
// either way (bounces alone need many rays to find the sun: 2048 per pixel against 64), and
// at equal rays far less noise between two seeds with it.
TEST(EnvironmentLight, SamplingItAgreesWithBouncesAndIsLessNoisy) {
  scene_description d = furnace(lambert(0.5f), 0, true);
  d.lights.clear();
  d.env.latlong_file = sky_with_sun();
  d.env.colour = glm::vec3(0);
  const scene s(d);
  auto render = [&](bool sample, uint32_t spp, uint64_t seed) {
    trace_params tp = path(1, spp);
    tp.sample_environment = sample, tp.seed = seed;
    return trace_reference(s, look_at({0, 0.5f, 3}, {0, -0.3f, 0}, 60), 32, 24, tp).image;
  };
  // Over the pixels that see geometry: the mean of two seeds' frames, the standard error of
  // that mean (from the seeds' differences: each has twice one frame's variance), and the
  // mean squared difference between the seeds.
  struct stats {
    double mean = 0, error = 0, noise = 0;
  };
  auto measure = [&](bool sample, uint32_t spp) {
    const frame a = render(sample, spp, 1), b = render(sample, spp, 2);
    stats out;
    size_t n = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
      if (!std::isfinite(a.depth[i])) continue;
      out.mean += a.rgb[i].g + b.rgb[i].g, out.noise += std::pow(a.rgb[i].g - b.rgb[i].g, 2), ++n;
    }
    out.mean /= 2.0 * double(n), out.noise /= double(n);
    out.error = std::sqrt(out.noise / 2 / (2.0 * double(n)));
    return out;
  };
  const stats with = measure(true, 64), without = measure(false, 2048), without_equal = measure(false, 64);
  EXPECT_NEAR(with.mean, without.mean, 4 * std::hypot(with.error, without.error));
  EXPECT_LT(with.noise, 0.25 * without_equal.noise) << "sampling the sun should cut the noise";
  std::printf("environment light: mean %.4f +- %.4f with (64 rays), %.4f +- %.4f without (2048); noise at 64 rays %.3f "
              "of bounces alone\n",
              with.mean, with.error, without.mean, without.error, with.noise / without_equal.noise);
}

// Emissive triangles sampled as lights (next-event estimation with MIS) against the known
// answer: a white-ish Lambertian ground (albedo 0.5) under a square emitter of radiance 10,
// 0.5 wide, 1 above it (its mesh at the origin, placed by its instance), in the dark. At the
// point below the emitter's centre the ground reflects albedo x radiance x the form factor
// of the square, 4 Fc(a/h, a/h) with a corner's Fc(x, y) = (x/sqrt(1+x^2) atan(y/sqrt(1+x^2))
// + y/sqrt(1+y^2) atan(x/sqrt(1+y^2))) / 2 pi. Seen through a 1-degree camera, the pixels
// cover a patch where the answer varies by far less than the tolerance. Bounces alone find
// the emitter on 7 % of their rays: the same answer, with far more noise at equal rays. A
// scene without emissive triangles traces the same, bit for bit, either way.
TEST(EmitterLight, AGroundUnderASquareEmitterReflectsItsFormFactor) {
  scene_description d = furnace(lambert(0.5f), 0);
  d.lights.clear();
  d.meshes[0] = ground(0, 50, 0);
  material glow;
  glow.base_colour = glm::vec4(0, 0, 0, 1);
  glow.emissive = glm::vec3(10);
  d.materials.push_back(glow);
  const float a = 0.25f, h = 1;
  d.meshes.push_back(ground(0, a, 1));
  d.instances.push_back({1, glm::translate(glm::mat4(1.0f), {0, h, 0}), ""});
  const scene s(d);
  auto corner = [](double x, double y) {
    return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
            y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
           (2 * pi);
  };
  const double expected = 0.5 * 10 * 4 * corner(a / h, a / h);
  struct stats {
    double mean = 0, error = 0, noise = 0;
  };
  auto measure = [&](bool sample, uint32_t spp) {
    auto render = [&](uint64_t seed) {
      trace_params tp = path(1, spp);
      tp.sample_emitters = sample, tp.seed = seed;
      return trace_reference(s, look_at({0, 0.5f, 0.5f}, {0, 0, 0}, 1), 16, 16, tp).image;
    };
    const frame f1 = render(1), f2 = render(2);
    stats out;
    for (size_t i = 0; i < f1.rgb.size(); ++i)
      out.mean += f1.rgb[i].g + f2.rgb[i].g, out.noise += std::pow(f1.rgb[i].g - f2.rgb[i].g, 2);
    const double n = double(f1.rgb.size());
    out.mean /= 2 * n, out.noise /= n;
    out.error = std::sqrt(out.noise / 2 / (2 * n));
    return out;
  };
  const stats with = measure(true, 64), without = measure(false, 1024), without_equal = measure(false, 64);
  EXPECT_NEAR(with.mean, expected, 4 * with.error + 1e-3 * expected);
  EXPECT_NEAR(without.mean, expected, 4 * without.error + 1e-3 * expected);
  EXPECT_LT(with.noise, 0.05 * without_equal.noise) << "sampling the emitter should cut the noise";
  std::printf("emitter light: expected %.4f, mean %.4f +- %.4f with (64 rays), %.4f +- %.4f without (1024); noise at 64 "
              "rays %.4f of bounces alone\n",
              expected, with.mean, with.error, without.mean, without.error, with.noise / without_equal.noise);

  const scene plain(furnace(lambert(0.5f), 1, true));
  trace_params on = path(2), off = path(2);
  off.sample_emitters = false;
  const camera view = look_at({0, 0.5f, 3}, {0, -0.3f, 0}, 70);
  EXPECT_EQ(trace_reference(plain, view, 20, 15, on).image.rgb, trace_reference(plain, view, 20, 15, off).image.rgb);
}

// A mirror reflects the environment: the centre of a sphere seen along -z reflects +z,
// the image's left and right edges (u = 0 or 1, the middle row), which are red; rays that
// graze the sphere's rim reflect towards -z, the image's blue centre.
TEST(EnvironmentLight, AMirrorReflectsTheExpectedTexel) {
  scene_description d = furnace(metal(0), 0);
  d.lights.clear();
  d.meshes[0] = sphere({0, 0, 0}, 1, 0, 96, 192);
  d.env.latlong_file = write_env("halves.exr", 64, 32, [](float s, float) {
    return s < 0.25f || s > 0.75f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  });
  const scene s(d);
  const int size = 41;
  const frame f = trace_reference(s, look_at({0, 0, 6}, {0, 0, 0}, 30), size, size, path(1, 4)).image;
  const glm::vec3 centre = f.rgb[size_t(size / 2) * size + size / 2];
  EXPECT_GT(centre.r, 0.9f);
  EXPECT_LT(centre.b, 0.05f);
  // Where the normal turns more than 45 degrees from the view (the outer part of the
  // disc), the reflection points behind the sphere: blue.
  int blue_rim = 0;
  for (int x = 0; x < size; ++x) {
    const glm::vec3 c = f.rgb[size_t(size / 2) * size + x];
    if (std::isfinite(f.depth[size_t(size / 2) * size + x]) && c.b > 0.9f) ++blue_rim;
  }
  EXPECT_GT(blue_rim, 0) << "the rim reflects what lies behind the sphere";
}

// The built-in room ("builtin:cornell", docs/tracer.md) is where bounces matter: its one
// downlight shines below the ceiling, so the direct integrator leaves the ceiling black
// (a black environment gives no ambient) and only light the room reflects reaches it;
// each bounce adds some.
TEST(Integrator, TheRoomsCeilingIsLitOnlyByBounces) {
  const auto s = load_scene("builtin:cornell");
  EXPECT_TRUE(s->warnings().empty());
  const camera cam = setup_camera(*s, {});
  const int w = 64, h = 72;
  // Pixels seeing the ceiling (y = 2, between the front edge at z = 1 and the back wall)
  // lie in rows 10-21 of 72 at the room's default 53-degree camera; rows 13-18, columns
  // 24-40 are well inside it.
  auto ceiling = [&](const frame& f) {
    double sum = 0;
    for (int y = 13; y <= 18; ++y)
      for (int x = 24; x <= 40; ++x) {
        const size_t i = size_t(y) * w + x;
        EXPECT_TRUE(std::isfinite(f.depth[i])) << x << "," << y;
        sum += f.rgb[i].g;
      }
    return sum / (6 * 17);
  };
  trace_params direct;
  direct.spp = 4;
  const double dark = ceiling(trace_reference(*s, cam, w, h, direct).image);
  const double one = ceiling(trace_reference(*s, cam, w, h, path(1, 64)).image);
  const double three = ceiling(trace_reference(*s, cam, w, h, path(3, 64)).image);
  EXPECT_EQ(dark, 0.0);
  EXPECT_GT(one, 0.02);
  EXPECT_GT(three, 1.1 * one);
}
