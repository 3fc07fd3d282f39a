// Scene files through Assimp and fovray's conversion: glTF 2.0 (text and binary) and OBJ,
// with a texture beside them (tex.png). The first byte picks the format, the rest is the
// file. A scene that loads must hold what the tracer indexes without checking.
#include <fstream>

#include "fov/files.h"
#include "fov/scene.h"
#include "fuzz_input.h"

using namespace fov;

namespace {

void write_texture() {  // a 2x2 grey PNG the seeds' materials refer to
  static const uint8_t png[] = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
      0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x00, 0x00, 0x00, 0x00, 0x57, 0xdd, 0x52, 0xf8, 0x00, 0x00, 0x00,
      0x0e, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x68, 0x68, 0x60, 0x68, 0x00, 0x00, 0x02, 0x84, 0x01, 0x01,
      0x6e, 0x6e, 0xa4, 0x3b, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  static const bool done = [] {
    fuzz::write_input(png, sizeof(png), "tex.png");
    return true;
  }();
  (void)done;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  write_texture();
  static const char* names[] = {"scene.gltf", "scene.glb", "scene.obj"};
  const std::string path = fuzz::write_input(data + 1, size - 1, names[data[0] % 3]);
  fuzz::expect_clean(path, [&] {
    const std::unique_ptr<scene> s = load_scene(path);
    const scene_description& d = s->description();
    for (const mesh& m : d.meshes) {
      for (const glm::uvec3& t : m.triangles)
        fuzz::require(t.x < m.positions.size() && t.y < m.positions.size() && t.z < m.positions.size(),
                      "triangle indices within the mesh");
      fuzz::require(m.material < d.materials.size(), "the material exists");
      fuzz::require(m.uvs.empty() || m.uvs.size() == m.positions.size(), "a uv per vertex");
      fuzz::require(m.normals.empty() || m.normals.size() == m.positions.size(), "a normal per vertex");
      fuzz::require(m.tangents.empty() || m.tangents.size() == m.positions.size(), "a tangent per vertex");
    }
    for (const instance& i : d.instances) fuzz::require(i.mesh < d.meshes.size(), "the instance's mesh exists");
    fuzz::require(geometry_problem(d).empty(), "the geometry Embree sees is finite and within range");
    if (d.scene_camera) {
      const glm::vec3& p = d.scene_camera->position;
      fuzz::require(world_point_problem(p.x, p.y, p.z).empty(), "the file's camera within range");
    }
    for (const std::string& f : d.files) fuzz::require(input_file_problem(f).empty(), "every file read is a regular file");
    for (const std::string& w : d.warnings) fuzz::require(w.find('\n') == std::string::npos, "warnings are one line");
  });
  return 0;
}
