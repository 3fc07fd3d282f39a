#include "fov/brdf.h"

#include <algorithm>
#include <cmath>

namespace fov {

namespace {

constexpr float pi = 3.14159265358979f;
constexpr float dielectric_f0 = 0.04f;  // ((1 - 1.5) / (1 + 1.5))^2

// An orthonormal basis (t, b, n) around a unit n (Duff et al. 2017's branchless form).
struct basis {
  glm::vec3 t, b, n;
  explicit basis(const glm::vec3& normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z), c = n.x * n.y * a;
    t = glm::vec3(1 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
  }
  glm::vec3 to_local(const glm::vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
  glm::vec3 to_world(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

float alpha_of(const brdf_inputs& m) { return std::max(m.roughness * m.roughness, min_brdf_alpha); }

// Trowbridge-Reitz distribution of normals at cos(n, h) = nh.
float ggx_d(float nh, float a2) {
  const float d = nh * nh * (a2 - 1) + 1;
  return a2 / (pi * d * d);
}
// Smith's masking of one direction at cos(n, x) = nx > 0.
float smith_g1(float nx, float a2) { return 2 * nx / (nx + std::sqrt(a2 + (1 - a2) * nx * nx)); }

float schlick(float f0, float vh) { return f0 + (1 - f0) * std::pow(1 - std::fabs(vh), 5.0f); }

// Heitz (2018): a normal of the GGX distribution of visible normals seen from `wo` (local,
// wo.z > 0), from two uniform numbers.
glm::vec3 sample_visible_normal(const glm::vec3& wo, float alpha, float u1, float u2) {
  const glm::vec3 vh = glm::normalize(glm::vec3(alpha * wo.x, alpha * wo.y, wo.z));
  const float len2 = vh.x * vh.x + vh.y * vh.y;
  const glm::vec3 t1 = len2 > 0 ? glm::vec3(-vh.y, vh.x, 0) / std::sqrt(len2) : glm::vec3(1, 0, 0);
  const glm::vec3 t2 = glm::cross(vh, t1);
  const float r = std::sqrt(u1), phi = 2 * pi * u2;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1 + vh.z);
  const float p2 = (1 - s) * std::sqrt(std::max(0.0f, 1 - p1 * p1)) + s * r * std::sin(phi);
  const glm::vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1 - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(glm::vec3(alpha * nh.x, alpha * nh.y, std::max(0.0f, nh.z)));
}

// The density of wi drawn through a visible normal, in local coordinates.
float specular_pdf(const glm::vec3& wo, const glm::vec3& wi, float a2) {
  const glm::vec3 h = glm::normalize(wo + wi);
  if (h.z <= 0 || wo.z <= 0) return 0;
  return smith_g1(wo.z, a2) * ggx_d(h.z, a2) / (4 * wo.z);
}

}  // namespace

float brdf_specular_share(const brdf_inputs& m) {
  // Half the draws for a dielectric's lobe (whose Fresnel weight reaches 1 at grazing
  // angles), all of them for a metal, which has no base.
  return 0.5f + 0.5f * std::clamp(m.metallic, 0.0f, 1.0f);
}

glm::vec3 brdf_eval(const brdf_inputs& m, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
  const float nl = glm::dot(n, wi), nv = glm::dot(n, wo);
  if (nl <= 0 || nv <= 0) return glm::vec3(0);
  const float alpha = alpha_of(m), a2 = alpha * alpha;
  const glm::vec3 h = glm::normalize(wo + wi);
  const float nh = std::max(glm::dot(n, h), 0.0f), vh = glm::dot(wo, h);
  // D G / (4 nl nv), with G the product of both directions' masking.
  const float specular = ggx_d(nh, a2) * smith_g1(nl, a2) * smith_g1(nv, a2) / (4 * nl * nv);
  const float metallic = std::clamp(m.metallic, 0.0f, 1.0f);
  const float fd = schlick(dielectric_f0, vh);
  const glm::vec3 dielectric = m.base_colour * (1 / pi) * (1 - fd) + glm::vec3(specular * fd);
  const float w = std::pow(1 - std::fabs(vh), 5.0f);
  const glm::vec3 metal = specular * (m.base_colour + (glm::vec3(1) - m.base_colour) * w);
  return dielectric * (1 - metallic) + metal * metallic;
}

float brdf_pdf(const brdf_inputs& m, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
  const basis frame(n);
  const glm::vec3 o = frame.to_local(wo), i = frame.to_local(wi);
  if (o.z <= 0 || i.z <= 0) return 0;
  const float alpha = alpha_of(m), share = brdf_specular_share(m);
  return share * specular_pdf(o, i, alpha * alpha) + (1 - share) * i.z / pi;
}

brdf_sample sample_brdf(const brdf_inputs& m, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& u) {
  brdf_sample out;
  const basis frame(n);
  const glm::vec3 o = frame.to_local(wo);
  if (o.z <= 0) return out;
  const float alpha = alpha_of(m), share = brdf_specular_share(m);
  glm::vec3 i;
  if (u.x < share) {  // the lobe: reflect wo about a visible normal
    const glm::vec3 h = sample_visible_normal(o, alpha, u.y, u.z);
    i = 2 * glm::dot(o, h) * h - o;
  } else {  // the base: cosine-weighted (a uniform point of the disc lifted to the hemisphere)
    const float r = std::sqrt(u.y), phi = 2 * pi * u.z;
    i = glm::vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1 - u.y)));
  }
  if (i.z <= 0) return out;
  out.wi = glm::normalize(frame.to_world(i));
  out.pdf = brdf_pdf(m, n, wo, out.wi);
  if (out.pdf <= 0) return out;
  out.weight = brdf_eval(m, n, wo, out.wi) * (glm::dot(n, out.wi) / out.pdf);
  return out;
}

}  // namespace fov
