// OpenCL tests need a device. Where none is found they skip, unless FOV_REQUIRE_OPENCL=1
// (.ci/run sets it): then they fail, so a broken OpenCL install cannot pass as green.
#pragma once

#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>

namespace fov {

inline bool opencl_required() {
  const char* v = std::getenv("FOV_REQUIRE_OPENCL");
  return v && std::strcmp(v, "1") == 0;
}

}  // namespace fov

// In a test body: fails (FOV_REQUIRE_OPENCL=1) or skips when `device` (a cl_reconstructor)
// has no OpenCL device.
#define FOV_REQUIRE_DEVICE(device)                                                                   \
  do {                                                                                               \
    if (!(device).available()) {                                                                     \
      if (::fov::opencl_required()) FAIL() << "no OpenCL device, and FOV_REQUIRE_OPENCL=1: " << (device).reason(); \
      GTEST_SKIP() << "no OpenCL device: " << (device).reason();                                     \
    }                                                                                                \
  } while (0)
