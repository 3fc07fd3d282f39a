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

// Canvas pixels per side of a refinement block (an adaptive frame, fov/adaptive.h).
inline constexpr uint32_t refinement_block = 16;

// Which level each block of the screen's part of the canvas reads.
struct refinement_map {
  canvas_offset offset;           // the canvas placement the map is for (samples.offset)
  bool mirror_x = false, mirror_y = false;  // and its mirroring (samples.mirror_x, mirror_y)
  uint32_t x0 = 0, y0 = 0;        // the first block's canvas pixel (a multiple of the block size)
  uint32_t blocks_x = 0, blocks_y = 0;
  std::vector<uint8_t> level;     // per block, row-major
  uint8_t at(uint32_t cx, uint32_t cy) const {  // the level canvas pixel (cx, cy) reads
    return level[size_t((cy - y0) / refinement_block) * blocks_x + (cx - x0) / refinement_block];
  }
};

// One level's pixels of a refinement map: a reconstruction given one rebuilds only the screen
// pixels whose block reads `level`, leaving the others as they were (C++) or unspecified
// (the device's frame); the adaptive frame takes each level's pixels from its own run.
struct level_mask {
  const refinement_map* map = nullptr;
  uint8_t level = 0;
};

// Screen pixel (sx, sy)'s canvas pixel under the samples' placement and mirroring.
inline void screen_to_canvas(const point_samples& s, int width, int height, int sx, int sy, uint32_t& cx, uint32_t& cy) {
  cx = uint32_t((s.mirror_x ? width - 1 - sx : sx) + s.offset.x);
  cy = uint32_t((s.mirror_y ? height - 1 - sy : sy) + s.offset.y);
}

}  // namespace fov
