// Scenes the tracer can render: triangle meshes with a small material model,
// one light, and an environment. Only what the scenes in use need (docs/tracer.md).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "fov/camera.h"

namespace fov {

// A texture file, read whole into a MIP pyramid when the scene is made (docs/tracer.md).
struct texture_ref {
  std::string file;   // empty: none
  bool srgb = true;   // colour data stored sRGB-encoded (decoded after filtering)
};

// Patterns the built-in scene computes instead of reading files; each is
// filtered analytically by the ray footprint.
enum class pattern : uint8_t { none, checker, glyphs, leaf };

// How a material reflects light: Lambert (the base colour alone; OBJ files and the built-in
// scene) or glTF 2.0's metallic-roughness model (fov/brdf.h; glTF files).
enum class shading_model : uint8_t { lambert, metallic_roughness };

// How a material's alpha (base colour factor x texture alpha) covers what lies behind it.
enum class alpha_mode : uint8_t {
  opaque,  // alpha ignored (glTF OPAQUE, the default)
  mask,    // a hit where alpha >= alpha_cutoff, none below (glTF MASK, OBJ map_d)
  blend,   // a hit with probability alpha, drawn per ray and surface: over many rays the
           // surface covers what lies behind it by alpha, as glTF BLEND's "over" (stochastic
           // transparency; shadow rays pass likewise)
};
inline constexpr std::pair<const char*, alpha_mode> alpha_mode_labels[] = {
    {"opaque", alpha_mode::opaque}, {"mask", alpha_mode::mask}, {"blend", alpha_mode::blend}};

struct material {
  std::string name;
  shading_model model = shading_model::lambert;
  glm::vec4 base_colour{0.8f, 0.8f, 0.8f, 1};  // linear RGB + alpha, times base_texture
  texture_ref base_texture;
  // metallic_roughness only: the factors (glTF's defaults), times the texture's blue
  // (metallic) and green (roughness) channels; the occlusion texture's red channel darkens
  // the ambient term of the direct integrator (a path tracer finds occlusion itself).
  float metallic = 1, roughness = 1;
  texture_ref metallic_roughness_texture;  // linear
  texture_ref occlusion_texture;           // linear
  float occlusion_strength = 1;
  glm::vec3 emissive{0, 0, 0};
  texture_ref emissive_texture;
  texture_ref normal_texture;  // tangent space, linear
  alpha_mode alpha = alpha_mode::opaque;
  float alpha_cutoff = 0.5f;  // mask only
  pattern procedural = pattern::none;
  float pattern_repeats = 1;  // pattern periods per UV unit
  glm::vec3 pattern_colour{0, 0, 0};  // the second colour of checker and glyph patterns
};

struct mesh {
  std::vector<glm::vec3> positions, normals;  // object space; normals may be empty
  std::vector<glm::vec4> tangents;            // xyz + handedness; may be empty
  std::vector<glm::vec2> uvs;                 // may be empty
  std::vector<glm::uvec3> triangles;
  uint32_t material = 0;
};

// One placement of a mesh: the node hierarchy flattened into instances.
struct instance {
  uint32_t mesh = 0;
  glm::mat4 transform{1.0f};
  std::string node;  // the file's node that places it (for messages)
};

struct light {
  enum class kind { directional, point, spot } type = kind::directional;
  glm::vec3 direction = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));  // directional: towards the light
  glm::vec3 position{0, 10, 0};  // point and spot
  // Spot: the unit direction it shines in, and the half-angles (radians) of its cone:
  // full intensity within `inner_cone`, none beyond `outer_cone`, between them glTF's
  // KHR_lights_punctual falloff (a clamped linear ramp in the cosine, squared).
  glm::vec3 axis{0, -1, 0};
  float inner_cone = 0, outer_cone = 0.785398163f;
  // Irradiance (directional) or intensity (point, spot), scaled so that a white Lambertian
  // surface facing the light shows it (glTF's lux and candela divided by pi). The default
  // keeps white albedo facing it, plus the default ambient (0.35 x the mean sky, about
  // 0.16), below 1: no clipping.
  glm::vec3 colour{0.8f, 0.77f, 0.7f};
};

// What rays that miss see, and the ambient light every surface gets.
struct environment {
  glm::vec3 colour{0.35f, 0.45f, 0.6f};  // constant colour (times intensity), when no map
  std::string latlong_file;              // lat-long image; see docs/tracer.md for the mapping
  float intensity = 1;
  float ambient = 0.35f;  // ambient = ambient * mean environment colour
};

struct scene_description {
  std::vector<mesh> meshes;
  std::vector<instance> instances;
  std::vector<material> materials;
  std::vector<light> lights{light()};  // every one lights every surface (the default: one sun)
  environment env;
  std::optional<camera> scene_camera;  // from the file, when it has one
  std::vector<std::string> warnings;   // one per problem item, in load order
  std::vector<std::string> files;      // every file it was read from (scene, buffers, images)
};

// How a placement (an instance's transform) scales its mesh, from its linear part and that
// part's inverse: within max_transform_scale either way; vanishing (finite, but shrinking the
// mesh below 1 / max_transform_scale: the loader skips such a node); or out of range (not
// finite, or growing the mesh beyond max_transform_scale).
enum class placement_scale { within, vanishing, out_of_range };
placement_scale classify_placement(const glm::mat4& transform);

// "" when Embree may be given the description's geometry, else why not (naming the mesh or
// node): every vertex finite and within max_world_coordinate (fov/camera.h) in its mesh and
// placed in the world; every placement finite, affine, and scaling its mesh by at most
// max_transform_scale either way; every instance of a mesh that exists. The scene
// constructor refuses (std::invalid_argument) what fails it; load_scene names the file.
std::string geometry_problem(const scene_description& d);

// A scene ready to trace: Embree BVH (two levels: meshes, instances), textures.
class scene {
 public:
  explicit scene(scene_description description);
  ~scene();
  scene(const scene&) = delete;
  scene& operator=(const scene&) = delete;

  const scene_description& description() const;
  const std::vector<std::string>& warnings() const { return description().warnings; }
  // The file's camera, or one that frames the scene bounds with this field of view.
  camera default_camera(float hfov_deg = 90) const;
  glm::vec3 bounds_min() const;
  glm::vec3 bounds_max() const;

  struct impl;
  const impl& internals() const { return *impl_; }

 private:
  std::unique_ptr<impl> impl_;
};

// What a user may change about a scene's camera; every tool applies it with setup_camera.
struct camera_overrides {
  float hfov_deg = 0;  // horizontal field of view in degrees, (0, 180); 0: the scene's own
  // Where the camera is and what it looks at (world units); each left unset keeps the
  // scene camera's: an eye alone keeps its direction, a target alone its position.
  std::optional<glm::vec3> eye, target, up;
};
// Returns the empty string when the overrides are valid, else the reason.
std::string validate(const camera_overrides& o);

// The camera a tool renders `s` with: the scene's default camera (the file's, else one
// framing its bounds) with the overrides applied, for every scene kind. Throws
// usage_error (fov/usage_error.h) naming the flag when the overrides cannot be used.
camera setup_camera(const scene& s, const camera_overrides& o = {});

// "builtin", "builtin:cornell", "env:FILE" (an environment image and no geometry) or a glTF 2.0 / OBJ
// file (through Assimp). Missing textures and degenerate triangles are warned about
// once each and skipped; an unreadable file throws std::runtime_error naming it. Every
// file a scene reads (the scene, its buffers, its images) must be a regular file of at most
// max_scene_file_bytes; a glTF's JSON is refused before Assimp parses it when it does not
// parse, repeats a key in an object (Assimp's reader would read it otherwise), nests
// deeper than max_gltf_json_depth or its node tree is deeper than max_node_depth, cyclic,
// or shares a node between parents (Assimp recurses once per level and crashed at 20,000),
// when a buffer claims more bytes than its file (Assimp allocates what it claims before
// reading), and when it has sparse accessors (Assimp writes their values unchecked).
// Meshes a node scales below 1 / max_transform_scale are skipped with a warning; the
// geometry must pass geometry_problem.
std::unique_ptr<scene> load_scene(const std::string& spec);
// The same scene lit and surrounded by a lat-long environment image (`env_light`, read as
// an env: scene's; "" for the scene's own environment): misses see it, the direct
// integrator's ambient term is its mean, the path integrator samples it as a light.
std::unique_ptr<scene> load_scene(const std::string& spec, const std::string& env_light);
// "" when `file` can be an environment image (a regular file OpenImageIO reads, at least
// 2x1 and at most max_env_pixels), else why not.
std::string env_image_problem(const std::string& file);

constexpr uintmax_t max_scene_file_bytes = uintmax_t(4) << 30;
constexpr int max_gltf_json_depth = 64;
constexpr int max_node_depth = 256;

// The largest env: image (width x height; 8192 x 4096): its float MIP pyramid takes about
// 0.5 GB. Larger images are refused with the size in the message.
constexpr int max_env_height = 4096;
constexpr uint64_t max_env_pixels = uint64_t(2 * max_env_height) * max_env_height;
// An env: image's texels are radiance: NaN or infinite ones and negative ones read as 0,
// ones above max_env_value (the largest half float) as max_env_value; each kind is
// counted in one warning naming the file.
constexpr float max_env_value = 65504.0f;

// The built-in procedural scene (no files; "builtin"): see docs/tracer.md.
scene_description builtin_scene();
// A Cornell-like room lit by one point light ("builtin:cornell"): coloured walls, a checker
// floor, a white box and a glossy metal one; where bounces matter (docs/tracer.md).
scene_description cornell_scene();
// Whether `spec` names a built-in scene (no file to check).
inline bool is_builtin_scene(const std::string& spec) { return spec == "builtin" || spec == "builtin:cornell"; }

}  // namespace fov
