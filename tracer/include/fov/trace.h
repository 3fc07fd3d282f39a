// Tracing: per-point colours for a foveated frame, and the full-resolution reference.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "fov/camera.h"
#include "fov/pointset.h"
#include "fov/scene.h"

namespace fov {

// Where tracing time goes, in thread-seconds summed over worker threads. Filled only
// when trace_params::timing points here: each stage costs two clock reads a packet.
struct trace_timing {
  double setup = 0;      // choosing points, generating rays
  double intersect = 0;  // rtcIntersect16 of primary rays
  double shade = 0;      // surface attributes, textures, environment
  double shadow = 0;     // rtcOccluded16 of shadow rays
  double total() const { return setup + intersect + shade + shadow; }
};

// The filter width of a traced point's ray for texture and environment lookups.
enum class texture_footprint {
  disc,   // its share of the point's disc, radius p / sqrt(spp): the point's colour is
          // prefiltered over its whole disc, as the thesis asks (default)
  pixel,  // a full-resolution pixel's share, radius 0.5 / sqrt(spp): sharper and, where
          // textures are minified, cheaper (one MIP level), but peripheral points alias
};
const char* texture_footprint_name(texture_footprint f);  // "disc" or "pixel"
bool parse_texture_footprint(const std::string& name, texture_footprint& out);

struct trace_params {
  uint32_t spp = 32;     // rays per point (foveated) or per pixel (reference)
  uint64_t seed = 1;     // fixes the ray positions: the same every frame
  bool shadows = true;   // hard shadows from the scene's light
  // Foveated only: use the point set mirrored left-right and/or top-bottom (thesis Sec.
  // 3.3: four patterns from one set, so TAA can blend frames with different samples).
  bool mirror_x = false, mirror_y = false;
  texture_footprint footprint = texture_footprint::disc;  // foveated only
  trace_timing* timing = nullptr;  // accumulates stage times when set
  // Reference only: when set, receives each 8 x 8-pixel tile's thread-seconds (row-major,
  // ceil(W / 8) x ceil(H / 8) tiles): a map of what rays cost where on the screen, so a
  // foveated frame's time can be compared with what the same content costs at full
  // resolution (tracer_bench's content-weighted ray ratio).
  std::vector<double>* tile_seconds = nullptr;
};
// The tiles of trace_params::tile_seconds.
constexpr int reference_tile = 8;

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

// Traces every point the screen needs for this gaze (traced_point_mask with k_used):
// each casts params.spp rays through uniform random positions in the disc of radius
// p around it (fixed per point: seeded by params.seed and the point's index).
point_samples trace_points(const scene& s, const camera& cam, const pointset& set, double gaze_x, double gaze_y,
                           uint32_t k_used, const trace_params& params);

// The screen positions (pixels) of the rays trace_points cast for `samples` (its traced
// points, placement and mirroring), in the order it cast them: params.spp per point.
// The same rays without the tracer, for a bare intersection loop over them.
std::vector<glm::vec2> point_ray_positions(const pointset& set, const point_samples& samples, const trace_params& params);

struct frame {
  int width = 0, height = 0;
  std::vector<glm::vec3> rgb;  // linear
  std::vector<float> depth;    // mean camera-space depth of hits; +inf where none
  uint64_t rays = 0;
};

// Full resolution: params.spp rays per pixel, jittered uniformly inside the pixel.
frame trace_reference(const scene& s, const camera& cam, int width, int height, const trace_params& params);

}  // namespace fov
