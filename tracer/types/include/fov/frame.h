// What the tracer produces and the reconstruction consumes: traced point samples and
// frames. A layer of plain types (with the camera and the gaze) that tracer/ and interp/
// both use, so interp/ needs neither Embree nor Assimp nor OpenImageIO.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "fov/pointset.h"

namespace fov {

// Per-point results, indexed like the point set (untraced points stay zero).
struct point_samples {
  std::vector<glm::vec3> colour;  // mean linear RGB of the point's rays
  std::vector<float> depth;       // mean camera-space depth of the rays that hit; +inf if none did
  std::vector<uint16_t> hits;     // rays that hit geometry
  std::vector<uint32_t> traced;   // the traced points, in Morton order
  canvas_offset offset;           // canvas = (mirrored) screen + offset for this gaze
  // The pattern was mirrored (trace_params): screen pixel (x, y) reads the table at
  // (W - 1 - x, y) and/or (x, H - 1 - y), with the offset of the mirrored gaze.
  bool mirror_x = false, mirror_y = false;
  uint64_t rays = 0;
};

// A screen image, row-major from the top-left pixel.
struct frame {
  int width = 0, height = 0;
  std::vector<glm::vec3> rgb;  // linear
  std::vector<float> depth;    // mean camera-space depth of hits; +inf where none
  uint64_t rays = 0;
};

}  // namespace fov
