// The glTF 2.0 metallic-roughness BRDF (the specification's Appendix B): a Trowbridge-Reitz
// (GGX) microfacet lobe with separable Smith masking-shadowing and Schlick's Fresnel,
// over a Lambertian base for dielectrics (index of refraction 1.5, F0 = 0.04), mixed
// with a metal whose F0 is the base colour by the metallic value. Evaluated, sampled and
// its density given for the integrators (docs/tracer.md, "Materials and integrators").
#pragma once

#include <glm/glm.hpp>

namespace fov {

struct brdf_inputs {
  glm::vec3 base_colour{1};  // linear RGB in [0, 1]
  float metallic = 0;        // [0, 1]
  float roughness = 1;       // perceptual roughness in [0, 1]; alpha = roughness^2
};

// The smallest alpha (roughness^2) the lobe is evaluated with: a perfect mirror's
// distribution is a delta, which neither evaluation nor a density can carry.
constexpr float min_brdf_alpha = 1e-3f;

// f(wo, wi) in 1/sr: n the unit shading normal, wo towards the viewer, wi towards the
// light (unit, world space). Zero when either direction is below the surface. Reciprocal:
// f(wo, wi) == f(wi, wo).
glm::vec3 brdf_eval(const brdf_inputs& m, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi);

// The density brdf_sample draws wi with (per steradian): a mixture of cosine-weighted
// directions (the base) and Heitz's visible-normal sampling of the GGX lobe, the lobe
// chosen with probability brdf_specular_share(m).
float brdf_pdf(const brdf_inputs& m, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi);
float brdf_specular_share(const brdf_inputs& m);

struct brdf_sample {
  glm::vec3 wi{0};
  glm::vec3 weight{0};  // f(wo, wi) cos(n, wi) / pdf; zero when the draw fell below the surface
  float pdf = 0;        // brdf_pdf(m, n, wo, wi)
};
// Draws wi from three uniform numbers in [0, 1).
brdf_sample sample_brdf(const brdf_inputs& m, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& u);

}  // namespace fov
