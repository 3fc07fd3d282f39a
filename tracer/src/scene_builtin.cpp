// The built-in scene: everything foveation struggles with, and no files.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "fov/scene.h"

namespace fov {

namespace {

constexpr float pi = 3.14159265358979323846f;

uint32_t add_material(scene_description& d, material m) {
  d.materials.push_back(std::move(m));
  return uint32_t(d.materials.size() - 1);
}

// A Lambertian material of one colour.
uint32_t add_plain(scene_description& d, const char* name, glm::vec3 c) {
  material m;
  m.name = name;
  m.base_colour = glm::vec4(c, 1);
  return add_material(d, m);
}

void add(scene_description& d, mesh m, const glm::mat4& transform = glm::mat4(1.0f)) {
  d.meshes.push_back(std::move(m));
  d.instances.push_back({uint32_t(d.meshes.size() - 1), transform, ""});
}

// A quad with corner `o` and edges `a`, `b`; UVs in world units along a and b.
mesh quad(glm::vec3 o, glm::vec3 a, glm::vec3 b, uint32_t mat) {
  mesh m;
  m.positions = {o, o + a, o + a + b, o + b};
  const glm::vec3 n = glm::normalize(glm::cross(a, b));
  m.normals = {n, n, n, n};
  const float la = glm::length(a), lb = glm::length(b);
  m.uvs = {{0, lb}, {la, lb}, {la, 0}, {0, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.material = mat;
  return m;
}

// An axis-aligned box centred at the origin with the given size.
mesh box(glm::vec3 size, uint32_t mat) {
  mesh m;
  const glm::vec3 h = 0.5f * size;
  const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {-1.0f, 1.0f}) {
      const glm::vec3 n = sign * axes[axis];
      const glm::vec3 u = axes[(axis + 1) % 3] * h[(axis + 1) % 3], v = axes[(axis + 2) % 3] * h[(axis + 2) % 3];
      const glm::vec3 c = n * h[axis];
      const auto base = uint32_t(m.positions.size());
      // Wind so the face's normal points outwards.
      const glm::vec3 uu = sign > 0 ? u : -u;
      m.positions.insert(m.positions.end(), {c - uu - v, c + uu - v, c + uu + v, c - uu + v});
      m.normals.insert(m.normals.end(), {n, n, n, n});
      const float lu = 2 * glm::length(u), lv = 2 * glm::length(v);
      m.uvs.insert(m.uvs.end(), {{0, lv}, {lu, lv}, {lu, 0}, {0, 0}});
      m.triangles.push_back({base, base + 1, base + 2});
      m.triangles.push_back({base, base + 2, base + 3});
    }
  m.material = mat;
  return m;
}

}  // namespace

scene_description builtin_scene() {
  scene_description d;
  material ground;
  ground.name = "checker ground";
  ground.base_colour = {0.85f, 0.85f, 0.85f, 1};
  ground.procedural = pattern::checker;
  ground.pattern_repeats = 4;  // 25 cm squares
  ground.pattern_colour = {0.04f, 0.04f, 0.04f};
  const uint32_t ground_m = add_material(d, ground);

  material text = ground;
  text.name = "glyph wall";
  text.base_colour = {0.9f, 0.88f, 0.8f, 1};
  text.procedural = pattern::glyphs;
  text.pattern_repeats = 2;  // 50 cm glyphs: about 9 px at 34 m on a 1280-px, 90-degree screen
  const uint32_t wall_m = add_material(d, text);
  text.name = "glyph poster";
  text.pattern_repeats = 4;  // 25 cm glyphs: about 20 px at 7 m
  const uint32_t poster_m = add_material(d, text);

  auto plain = [&](const char* name, glm::vec3 c) { return add_plain(d, name, c); };
  const uint32_t white = plain("white", {0.9f, 0.9f, 0.9f}), black = plain("black", {0.02f, 0.02f, 0.02f});
  const uint32_t red = plain("red", {0.8f, 0.05f, 0.03f}), blue = plain("blue", {0.05f, 0.1f, 0.7f});
  const uint32_t metal = plain("pole", {0.15f, 0.15f, 0.17f});

  material leaf;
  leaf.name = "leaf (alpha mask)";
  leaf.base_colour = {0.1f, 0.45f, 0.08f, 1};
  leaf.procedural = pattern::leaf;
  leaf.alpha = alpha_mode::mask;
  const uint32_t leaf_m = add_material(d, leaf);

  material sign;
  sign.name = "emissive sign";
  sign.base_colour = {0.1f, 0.1f, 0.1f, 1};
  sign.emissive = {4.0f, 3.2f, 1.6f};
  const uint32_t sign_m = add_material(d, sign);

  // Ground 80 m x 90 m, a wall of text 34 m away, a poster of larger text 7 m away.
  add(d, quad({-40, 0, 10}, {80, 0, 0}, {0, 0, -90}, ground_m));
  add(d, quad({-10, 0, -30}, {20, 0, 0}, {0, 8, 0}, wall_m));
  add(d, quad({-3.2f, 0.4f, -3}, {2, 0, 0}, {0, 1.4f, 0}, poster_m));

  // High-contrast boxes over a wide depth range.
  add(d, box({1, 1, 1}, white), glm::translate(glm::mat4(1), {1.5f, 0.5f, -2}));
  add(d, box({1.5f, 1.5f, 1.5f}, black), glm::translate(glm::mat4(1), {-1, 0.75f, -6}));
  add(d, box({2, 2, 2}, red), glm::rotate(glm::translate(glm::mat4(1), {4, 1, -15}), 0.5f, {0, 1, 0}));
  add(d, box({4, 4, 4}, blue), glm::translate(glm::mat4(1), {-26, 2, -60}));

  // Thin geometry: ten 2 cm poles (one mesh, ten instances) and 1 cm wires between them.
  d.meshes.push_back(box({0.02f, 4, 0.02f}, metal));
  const uint32_t pole = uint32_t(d.meshes.size() - 1);
  for (int i = 0; i < 10; ++i)
    d.instances.push_back({pole, glm::translate(glm::mat4(1), {-4.5f + i, 2, -8}), "pole"});
  for (float y : {3.2f, 3.5f, 3.8f}) add(d, box({9, 0.01f, 0.01f}, metal), glm::translate(glm::mat4(1), {0, y, -8}));

  // An alpha-masked plant: 24 leaves around a stem, tilted outwards.
  mesh leaves;
  leaves.material = leaf_m;
  for (int i = 0; i < 24; ++i) {
    const float phi = 2 * pi * float(i) / 24 + 0.3f * float(i % 3), tilt = 0.3f + 0.15f * float(i % 4);
    const float height = 0.2f + 0.05f * float(i % 6);
    const glm::vec3 out(std::cos(phi), 0, std::sin(phi)), side(-std::sin(phi), 0, std::cos(phi));
    const glm::vec3 along = glm::normalize(out * std::sin(tilt) + glm::vec3(0, std::cos(tilt), 0));
    const glm::vec3 o = glm::vec3(0, height, 0) - 0.12f * side;
    const auto base = uint32_t(leaves.positions.size());
    const glm::vec3 a = 0.24f * side, b = 0.7f * along;
    leaves.positions.insert(leaves.positions.end(), {o, o + a, o + a + b, o + b});
    const glm::vec3 n = glm::normalize(glm::cross(a, b));
    leaves.normals.insert(leaves.normals.end(), {n, n, n, n});
    leaves.uvs.insert(leaves.uvs.end(), {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    leaves.triangles.push_back({base, base + 1, base + 2});
    leaves.triangles.push_back({base, base + 2, base + 3});
  }
  add(d, std::move(leaves), glm::translate(glm::mat4(1), {3.3f, 0, -3.5f}));

  add(d, quad({2.0f, 2.6f, -10}, {1.6f, 0, 0}, {0, 0.5f, 0}, sign_m));

  d.lights.at(0).direction = glm::normalize(glm::vec3(0.5f, 1.0f, 0.4f));
  // Brighter than the default light: the test pattern's whites clip on screen
  // (docs/tracer.md); --exposure or --sun-irradiance bring them back.
  d.lights.at(0).colour = {2.5f, 2.4f, 2.2f};
  d.env.colour = {0.35f, 0.45f, 0.65f};
  d.scene_camera = look_at({0, 1.6f, 4}, {0, 0.6f, -10}, 90);
  return d;
}

scene_description cornell_scene() {
  scene_description d;
  auto lambert = [&](const char* name, glm::vec3 c) { return add_plain(d, name, c); };
  const uint32_t white = lambert("white", {0.73f, 0.73f, 0.73f}), red = lambert("red", {0.63f, 0.065f, 0.05f});
  const uint32_t green = lambert("green", {0.14f, 0.45f, 0.09f});
  material floor = d.materials[white];
  floor.name = "checker floor";
  floor.procedural = pattern::checker;
  floor.pattern_repeats = 4;  // 25 cm squares, as the built-in scene's ground
  floor.pattern_colour = {0.08f, 0.08f, 0.08f};
  const uint32_t floor_m = add_material(d, floor);
  material metal;
  metal.name = "brushed metal";
  metal.model = shading_model::metallic_roughness;
  metal.base_colour = {0.95f, 0.93f, 0.88f, 1};
  metal.metallic = 1;
  metal.roughness = 0.45f;
  const uint32_t metal_m = add_material(d, metal);

  // A 2 m room open towards the camera: floor y = 0, ceiling y = 2, walls at x = -1 (red),
  // x = 1 (green) and z = -1; every face's normal points into the room.
  add(d, quad({-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, floor_m));
  add(d, quad({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, white));
  add(d, quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, white));
  add(d, quad({-1, 0, 1}, {0, 0, -2}, {0, 2, 0}, red));
  add(d, quad({1, 0, -1}, {0, 0, 2}, {0, 2, 0}, green));
  // A short white box and a tall glossy metal one.
  add(d, box({0.6f, 0.6f, 0.6f}, white), glm::rotate(glm::translate(glm::mat4(1), {0.38f, 0.3f, 0.3f}), -0.3f, {0, 1, 0}));
  add(d, box({0.6f, 1.2f, 0.6f}, metal_m), glm::rotate(glm::translate(glm::mat4(1), {-0.35f, 0.6f, -0.35f}), 0.35f, {0, 1, 0}));

  // One downlight at the ceiling's centre (a spot: the ceiling is lit only by what the
  // room reflects), nothing outside: the direct integrator (no ambient from a black
  // environment) shows only what the light reaches straight.
  light lamp;
  lamp.type = light::kind::spot;
  lamp.position = {0, 1.98f, 0};
  lamp.axis = {0, -1, 0};
  lamp.inner_cone = 1.0f, lamp.outer_cone = 1.3f;
  lamp.colour = {2.4f, 2.3f, 2.15f};  // about 0.6 on the floor below it
  d.lights = {lamp};
  d.env.colour = {0, 0, 0};
  d.scene_camera = look_at({0, 1, 3.4f}, {0, 1, 0}, 53);
  return d;
}

}  // namespace fov
