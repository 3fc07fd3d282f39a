// The scene's emissive triangles as lights (scene_impl.h, emitter_set).
#include <algorithm>
#include <cmath>

#include "scene_impl.h"

namespace fov {

namespace {
uint64_t key(unsigned inst, unsigned prim) { return (uint64_t(inst) << 32) | prim; }
}  // namespace

emitter_set make_emitter_set(const scene_description& d) {
  emitter_set out;
  std::vector<double> power;
  for (size_t i = 0; i < d.instances.size(); ++i) {
    const instance& in = d.instances[i];
    const mesh& m = d.meshes[in.mesh];
    const material& mat = d.materials[m.material];
    if (mat.alpha != alpha_mode::opaque) continue;
    const double emitted = luminance(mat.emissive);
    if (!(emitted > 0)) continue;
    for (size_t k = 0; k < m.triangles.size(); ++k) {
      const glm::uvec3 t = m.triangles[k];
      emitter_set::triangle tri;
      tri.inst = unsigned(i), tri.prim = unsigned(k);
      tri.p0 = glm::vec3(in.transform * glm::vec4(m.positions[t.x], 1));
      tri.e1 = glm::vec3(in.transform * glm::vec4(m.positions[t.y], 1)) - tri.p0;
      tri.e2 = glm::vec3(in.transform * glm::vec4(m.positions[t.z], 1)) - tri.p0;
      const glm::vec3 cross = glm::cross(tri.e1, tri.e2);
      tri.area = 0.5f * glm::length(cross);
      if (!(tri.area > 0) || !std::isfinite(tri.area)) continue;
      tri.normal = cross / (2 * tri.area);
      out.index.emplace(key(tri.inst, tri.prim), uint32_t(out.triangles.size()));
      out.triangles.push_back(tri);
      power.push_back(emitted * tri.area);
    }
  }
  double total = 0;
  for (double p : power) total += p;
  if (!(total > 0) || !std::isfinite(total)) return emitter_set();
  out.cdf.resize(power.size() + 1, 0.0f);
  out.density.resize(power.size());
  double sum = 0;
  for (size_t k = 0; k < power.size(); ++k) {
    out.density[k] = float(power[k] / total) / out.triangles[k].area;
    sum += power[k];
    out.cdf[k + 1] = float(sum / total);
  }
  out.cdf.back() = 1.0f;
  return out;
}

emitter_set::sample emitter_set::draw(float u0, float u1, float u2) const {
  sample s;
  // The first triangle whose cumulative probability exceeds u0 (one of non-zero probability).
  const auto it = std::upper_bound(cdf.begin() + 1, cdf.end(), u0);
  s.triangle = uint32_t(std::min<ptrdiff_t>(it - cdf.begin() - 1, ptrdiff_t(triangles.size()) - 1));
  // Uniform over the triangle: barycentrics from the square root warp.
  const float r = std::sqrt(u1);
  s.u = r * (1 - u2), s.v = r * u2;
  s.area_pdf = density[s.triangle];
  return s;
}

float emitter_set::area_pdf(unsigned inst, unsigned prim) const {
  const auto it = index.find(key(inst, prim));
  return it == index.end() ? 0.0f : density[it->second];
}

}  // namespace fov
