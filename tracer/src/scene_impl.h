// Internals shared by the scene and the tracer: Embree handles, texture access, shading inputs.
#pragma once

#include <embree3/rtcore.h>

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "fov/colour.h"
#include "fov/scene.h"

namespace fov {

struct geometry_data {
  const mesh* m = nullptr;
  const material* mat = nullptr;
  const scene::impl* owner = nullptr;
};

// Surface attributes at a hit, in world space.
struct surface {
  glm::vec3 position, normal, geometric_normal;
  glm::vec2 uv{0, 0};
  float uv_per_world = 0;  // UV units per world unit (isotropic estimate)
  const material* mat = nullptr;
  const mesh* m = nullptr;
  glm::vec4 tangent{0, 0, 0, 0};
};

// No image past this many texels is read (a header may claim any size): 16384 x 16384.
constexpr uint64_t max_image_texels = uint64_t(1) << 28;
// Nor one wider or taller than this: OpenImageIO's scanline reading allocates far more than
// the pixels of a very wide image (a fuzz finding, docs/fuzzing.md).
constexpr int max_image_side = 1 << 16;

// A material texture as a MIP pyramid in memory, four channels (grey read as RGB, a missing
// alpha as 1), values as the file holds them (sRGB ones are decoded after filtering, as a
// texture unit does). Each level halves the one above, each texel the mean of the area it
// covers (tracer/src/textures.cpp).
// This replaced OpenImageIO's TextureSystem, whose per-lookup cost (tile cache, per-thread
// state) was most of a textured scene's shading time (docs/benchmarks.md).
struct texture_pyramid {
  struct level {
    int width = 0, height = 0;
    std::vector<uint8_t> bytes;  // RGBA, row-major, row 0 at the top (t = 0): from 8-bit files
    std::vector<float> floats;   // the same from deeper files (16-bit, half, float)
  };
  std::vector<level> levels;
  // Filtered value at uv (periodic both ways) over a footprint of duv UV units: bilinear in
  // the two levels around the footprint, linear between them (trilinear, isotropic).
  glm::vec4 lookup(glm::vec2 uv, float duv) const;
};
// Reads `file` whole. Throws std::runtime_error naming the file.
texture_pyramid load_texture_pyramid(const std::string& file);

// A material's textures, each read once per scene (materials naming the same file share it);
// null where the material has none or its file could not be read (a warning said which).
struct material_textures {
  const texture_pyramid* base = nullptr;
  const texture_pyramid* emissive = nullptr;
  const texture_pyramid* normal = nullptr;
  const texture_pyramid* metallic_roughness = nullptr;
  const texture_pyramid* occlusion = nullptr;
};

// A lat-long environment image as a MIP pyramid in memory (levels built as a
// texture_pyramid's). One environment lookup per ray is the whole cost of an env: scene,
// and a TextureSystem call per ray made that cost dominate (docs/fovview.md has the
// measurement); this lookup is a trilinear read: two bilinear taps at the MIP level the
// footprint asks for.
struct env_pyramid {
  struct level {
    int width = 0, height = 0;
    std::vector<glm::vec3> texels;  // linear RGB, row-major, row 0 at the top (+y)
  };
  std::vector<level> levels;
  uint64_t non_finite = 0;  // texel values of the image that were NaN or infinite (read as 0)
  uint64_t negative = 0;    // negative texel values (read as 0)
  uint64_t too_bright = 0;  // texel values above max_env_value (read as max_env_value)
  // Filtered value at (s, t) in [0, 1] (s periodic, t clamped) over a footprint of ds x dt.
  glm::vec3 lookup(float s, float t, float ds, float dt) const;
};
// Reads `file` (float formats as linear; 8-bit formats sRGB-decoded). Throws std::runtime_error.
env_pyramid load_env_pyramid(const std::string& file);

// Directions drawn in proportion to a lat-long environment's luminance times sin(theta)
// (a texel's solid angle), over the first level of its pyramid at most 1024 texels wide,
// uniformly within a texel; each texel's weight has a floor of 1 % of the mean, so every
// direction can be drawn (the lookup's filter reaches past a black texel).
struct env_sampler {
  int width = 0, height = 0;
  std::vector<float> rows;     // cumulative row probabilities, height + 1 entries
  std::vector<float> columns;  // per row, its cumulative column probabilities: width + 1 entries each
  std::vector<float> texel;    // each texel's probability
  bool empty() const { return texel.empty(); }
  // A direction from two uniform numbers in [0, 1), and its density per steradian.
  glm::vec3 sample(float u1, float u2, float& pdf) const;
  float pdf(const glm::vec3& dir) const;
};
env_sampler make_env_sampler(const env_pyramid& p);

// The scene's emissive triangles as lights for the path integrator (next-event estimation):
// every triangle of an opaque material with a non-zero emissive factor, in world space, drawn
// in proportion to its area times the luminance of its emissive factor (a textured emission
// is drawn by its factor and evaluated at the point drawn), then uniformly over its area.
// Masked and blended emitters are left out: they light by BRDF-sampled bounces alone.
struct emitter_set {
  struct triangle {
    unsigned inst = 0, prim = 0;  // the instance and its mesh's triangle, as Embree reports a hit
    glm::vec3 p0{0}, e1{0}, e2{0};
    glm::vec3 normal{0};  // unit, geometric
    float area = 0;
  };
  std::vector<triangle> triangles;
  std::vector<float> cdf;  // cumulative probabilities, triangles.size() + 1 entries
  std::vector<float> density;  // each triangle's probability per unit of its area
  std::unordered_map<uint64_t, uint32_t> index;  // (inst << 32) | prim -> triangle
  bool empty() const { return triangles.empty(); }
  // A point drawn from three uniform numbers in [0, 1): its triangle and barycentrics (u, v)
  // as Embree gives a hit's, and the density per unit area.
  struct sample {
    uint32_t triangle = 0;
    float u = 0, v = 0, area_pdf = 0;
  };
  sample draw(float u0, float u1, float u2) const;
  // The density per unit area of drawing a point on instance `inst`'s triangle `prim` (0: not an emitter).
  float area_pdf(unsigned inst, unsigned prim) const;
};
emitter_set make_emitter_set(const scene_description& d);

struct scene::impl {
  scene_description desc;
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  std::vector<RTCScene> mesh_scenes;
  std::vector<geometry_data> geometry;  // per mesh
  std::vector<glm::mat3> normal_matrix;  // per instance
  std::vector<uint8_t> identity_instance;  // per instance: its transform is the identity (surface_at skips it)
  std::vector<std::unique_ptr<texture_pyramid>> texture_images;  // each file once
  std::vector<material_textures> textures;                        // per material
  env_pyramid env_map;
  env_sampler env_light;  // when has_env_map
  emitter_set emitters;
  glm::vec3 bmin{0}, bmax{0};
  glm::vec3 env_mean{0};
  bool has_env_map = false;

  // Base colour (linear RGB, alpha) at uv filtered over duv UV units.
  glm::vec4 base_colour(const material& mat, glm::vec2 uv, float duv) const;
  glm::vec3 emission(const material& mat, glm::vec2 uv, float duv) const;
  // (metallic, roughness) of a metallic_roughness material: factors times texture.
  glm::vec2 metallic_roughness(const material& mat, glm::vec2 uv, float duv) const;
  // Ambient occlusion in [0, 1] (1: none): 1 + strength (texture red - 1).
  float occlusion(const material& mat, glm::vec2 uv, float duv) const;
  // Tangent-space normal map value in [-1, 1]^3, or (0, 0, 1) without a map.
  glm::vec3 normal_map(const material& mat, glm::vec2 uv, float duv) const;
  // Environment radiance seen along `dir`, filtered over `angle` radians.
  glm::vec3 environment_radiance(const glm::vec3& dir, float angle) const;
  // Fills `s` for a hit of instance `inst`, primitive `prim` at barycentrics (u, v).
  void surface_at(unsigned inst, unsigned prim, float u, float v, surface& s) const;
  const material_textures& textures_of(const material& mat) const { return textures[size_t(&mat - desc.materials.data())]; }
};

// Procedural patterns, filtered over a box of width w pattern units.
float filtered_checker(glm::vec2 p, float w);
float filtered_glyphs(glm::vec2 p, float w);
float leaf_alpha(glm::vec2 uv);

}  // namespace fov
