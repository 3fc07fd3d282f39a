#include <cmath>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "fov/cl_reconstruct.h"
#include "fov/dart_throwing.h"
#include "fov/knn_table.h"

namespace fov {
namespace {

struct device_fixture : ::testing::Test {
  pointset set;
  point_samples samples;
  void SetUp() override {
    set.model.display = {56, 48, 1.0};
    set.points = throw_darts(set.model, {});
    knn_params kp;
    kp.k = 32;
    kp.group = 4;
    set.table = build_knn_table(set.points, 112, 96, kp);
    samples.offset = offset_for_gaze(set.model.display, 20, 30);
    std::mt19937 random(9);
    std::uniform_real_distribution<float> u(0, 1);
    samples.colour.resize(set.points.size());
    samples.depth.resize(set.points.size());
    for (size_t i = 0; i < set.points.size(); ++i) {
      samples.colour[i] = {u(random), u(random), u(random)};
      samples.depth[i] = i % 7 == 0 ? INFINITY : 1 + 10 * u(random);  // some points hit nothing
    }
  }
};

TEST_F(device_fixture, KernelsMatchTheCppPathOnRandomFields) {
  cl_reconstructor device(set);
  if (!device.available()) GTEST_SKIP() << "no OpenCL device: " << device.reason();
  std::cout << "OpenCL device: " << device.device() << "\n";
  for (method m : {method::nn, method::shepard})
    for (uint32_t k : {1u, 5u, 10u, 20u, 32u})
      for (bool renka : {false, true}) {
        if (m == method::nn && (k != 1 || renka)) continue;
        reconstruct_params rp;
        rp.how = m;
        rp.k = k;
        rp.renka = renka;
        bool on_device = false;
        const frame a = device.run(samples, rp, &on_device);
        const frame b = reconstruct(set, samples, rp);
        ASSERT_TRUE(on_device);
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        for (size_t i = 0; i < a.rgb.size(); ++i) {
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(a.rgb[i][c], b.rgb[i][c], 1e-4) << method_name(m) << " k=" << k << " renka=" << renka << " pixel " << i;
          if (std::isinf(b.depth[i])) {
            ASSERT_TRUE(std::isinf(a.depth[i]));
          } else {
            ASSERT_NEAR(a.depth[i], b.depth[i], 1e-4 * b.depth[i]) << "depth, pixel " << i;
          }
        }
      }
}

TEST_F(device_fixture, KernelsReproduceAConstantField) {
  cl_reconstructor device(set);
  if (!device.available()) GTEST_SKIP() << "no OpenCL device: " << device.reason();
  for (glm::vec3& c : samples.colour) c = {0.25f, 0.5f, 0.75f};
  for (uint32_t k : {1u, 2u, 5u, 10u, 20u, 32u}) {
    reconstruct_params rp;
    rp.k = k;
    const frame f = device.run(samples, rp);
    for (const glm::vec3& c : f.rgb) {
      ASSERT_NEAR(c.r, 0.25f, 1e-5 * 0.25f) << "k=" << k;
      ASSERT_NEAR(c.b, 0.75f, 1e-5 * 0.75f) << "k=" << k;
    }
  }
}

TEST_F(device_fixture, RbfRunsOnTheCppPath) {
  cl_reconstructor device(set);
  reconstruct_params rp;
  rp.how = method::rbf;
  bool on_device = true;
  const frame a = device.run(samples, rp, &on_device);
  EXPECT_FALSE(on_device);
  EXPECT_EQ(a.rgb, reconstruct(set, samples, rp).rgb);
}

}  // namespace
}  // namespace fov
