// The glTF metallic-roughness BRDF (fov/brdf.h): reciprocity, energy, and its sampling
// consistent with its value and density.
#include <cmath>

#include <gtest/gtest.h>

#include "fov/brdf.h"
#include "fov/random.h"

using namespace fov;

namespace {

constexpr float pi = 3.14159265358979f;

glm::vec3 direction(float cos_theta, float phi) {
  const float s = std::sqrt(std::max(0.0f, 1 - cos_theta * cos_theta));
  return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

glm::vec3 uniform3(rng& r) { return {float(r.uniform()), float(r.uniform()), float(r.uniform())}; }

struct estimate {
  double mean = 0, error = 0;  // the mean and its standard error
};
template <class F>
estimate monte_carlo(int n, F&& draw) {
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = draw();
    sum += x, sum2 += x * x;
  }
  estimate e;
  e.mean = sum / n;
  e.error = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / n);
  return e;
}

// The share of light arriving from wo that the surface reflects (green channel), by
// the BRDF's own sampling.
estimate albedo_sampled(const brdf_inputs& m, const glm::vec3& n, const glm::vec3& wo, int count, uint64_t seed) {
  rng r(seed);
  return monte_carlo(count, [&] { return double(sample_brdf(m, n, wo, uniform3(r)).weight.g); });
}
// A direction given in the frame (t, b, n) of a unit normal n.
glm::vec3 around(const glm::vec3& n, const glm::vec3& local) {
  const glm::vec3 t = glm::normalize(glm::cross(n, std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
  return local.x * t + local.y * glm::cross(n, t) + local.z * n;
}

// The same by uniform directions over the hemisphere.
estimate albedo_uniform(const brdf_inputs& m, const glm::vec3& n, const glm::vec3& wo, int count, uint64_t seed) {
  rng r(seed);
  return monte_carlo(count, [&] {
    const glm::vec3 local = direction(float(r.uniform()), float(2 * pi * r.uniform()));
    return double(brdf_eval(m, n, wo, around(n, local)).g * local.z * 2 * pi);
  });
}

}  // namespace

TEST(Brdf, IsReciprocal) {
  rng r(3);
  const glm::vec3 n(0, 0, 1);
  for (int i = 0; i < 2000; ++i) {
    brdf_inputs m;
    m.base_colour = glm::vec3(r.uniform(), r.uniform(), r.uniform());
    m.metallic = float(r.uniform()), m.roughness = float(r.uniform());
    const glm::vec3 a = direction(float(r.uniform()), float(2 * pi * r.uniform()));
    const glm::vec3 b = direction(float(r.uniform()), float(2 * pi * r.uniform()));
    const glm::vec3 ab = brdf_eval(m, n, a, b), ba = brdf_eval(m, n, b, a);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(ab[c], ba[c], 1e-5f * std::max(1.0f, ab[c])) << i;
    EXPECT_EQ(brdf_eval(m, n, a, -b), glm::vec3(0)) << "below the surface";
  }
}

// Sampling agrees with evaluation: the albedo by the BRDF's importance sampling (its
// weights f cos / pdf) equals the albedo by uniform directions, for dielectrics and metals,
// rough and glossy, from normal to grazing incidence. A wrong density or weight shifts it.
TEST(Brdf, SamplingAgreesWithEvaluation) {
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.2f, 1));  // any frame
  uint64_t seed = 10;
  for (float metallic : {0.0f, 0.5f, 1.0f})
    for (float roughness : {0.3f, 0.6f, 1.0f})
      for (float cos_o : {1.0f, 0.5f, 0.15f}) {
        const brdf_inputs m{glm::vec3(0.7f, 0.5f, 0.3f), metallic, roughness};
        const glm::vec3 wo = around(n, direction(cos_o, 0.7f));
        const estimate s = albedo_sampled(m, n, wo, 200000, ++seed), u = albedo_uniform(m, n, wo, 400000, ++seed);
        EXPECT_NEAR(s.mean, u.mean, 4 * std::hypot(s.error, u.error))
            << "metallic " << metallic << " roughness " << roughness << " cos " << cos_o;
      }
}

// The density integrates to at most 1 over the hemisphere: draws that fall below it are
// lost, not moved. Known answers at normal incidence: at roughness 1 (alpha 1) the visible
// normals are cosine-distributed and half their reflections fall below the horizon, so a
// metal keeps 1/2 and a dielectric (half its draws cosine-weighted) 3/4; a smooth lobe
// keeps nearly all.
TEST(Brdf, DensityIntegratesToAtMostOne) {
  const glm::vec3 n(0, 0, 1);
  uint64_t seed = 50;
  for (float metallic : {0.0f, 1.0f})
    for (float roughness : {0.3f, 1.0f})
      for (float cos_o : {1.0f, 0.3f}) {
        const brdf_inputs m{glm::vec3(0.5f), metallic, roughness};
        const glm::vec3 wo = direction(cos_o, 0.2f);
        rng r(++seed);
        const estimate e = monte_carlo(400000, [&] {
          const glm::vec3 wi = direction(float(r.uniform()), float(2 * pi * r.uniform()));
          return double(brdf_pdf(m, n, wo, wi) * 2 * pi);
        });
        EXPECT_LE(e.mean, 1 + 4 * e.error) << metallic << " " << roughness << " " << cos_o;
        if (cos_o == 1.0f && roughness == 1.0f) {
          EXPECT_NEAR(e.mean, metallic == 1 ? 0.5 : 0.75, 4 * e.error);
        }
        if (cos_o == 1.0f && roughness < 1.0f) {
          EXPECT_GT(e.mean, 0.97);
        }
      }
}

// The weak furnace: a metal whose base colour is white absorbs nothing, so it reflects at
// most what arrives, at every roughness and angle. Single scattering loses the light that
// would bounce between microfacets: almost none where the surface is smooth; at roughness 1
// and normal incidence (D = 1/pi, G1(v) = 1, G1(l) = 2 cos / (cos + 1)) it keeps exactly
// 1 - ln 2.
TEST(Brdf, AWhiteMetalNeverReflectsMoreThanArrives) {
  const glm::vec3 n(0, 0, 1);
  uint64_t seed = 100;
  for (float roughness : {0.0f, 0.05f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f})
    for (float cos_o : {1.0f, 0.7f, 0.3f, 0.1f}) {
      const brdf_inputs m{glm::vec3(1), 1, roughness};
      const estimate e = albedo_sampled(m, n, direction(cos_o, 0), 100000, ++seed);
      EXPECT_LE(e.mean, 1 + 4 * e.error + 1e-4) << "roughness " << roughness << " cos " << cos_o;
      if (roughness <= 0.1f) {
        EXPECT_GT(e.mean, 0.99) << "roughness " << roughness << " cos " << cos_o;
      }
      if (roughness == 1.0f && cos_o == 1.0f) {
        EXPECT_NEAR(e.mean, 1 - std::log(2.0), 4 * e.error);
      }
    }
}
