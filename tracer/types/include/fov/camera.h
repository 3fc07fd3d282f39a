// Pinhole camera: screen pixels to rays and back.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace fov {

// The largest |coordinate| (world units) of anything placed in the world: a camera's eye
// and target (flags, camera path rows) and a scene's vertices, in their mesh and placed.
// Embree aborts on a ray whose origin lies beyond about 1.8e18 (its FLT_LARGE), and
// instances carry rays into their meshes' coordinates through inverse transforms of up to
// max_transform_scale: 1e9 keeps every ray of such scenes inside Embree's range.
constexpr double max_world_coordinate = 1e9;
// The most a placement (a glTF node's transform, composed) may scale its mesh, or the
// inverse: scenes scaled by more are refused, meshes scaled below its inverse are skipped.
constexpr double max_transform_scale = 1e6;

// "" when (x, y, z) is finite and within max_world_coordinate, else why not.
std::string world_point_problem(double x, double y, double z);

struct camera {
  glm::vec3 position{0, 0, 0};
  glm::vec3 forward{0, 0, -1};  // unit view direction
  glm::vec3 up{0, 1, 0};        // roughly up; re-orthogonalised against forward
  float hfov_deg = 90;          // horizontal field of view
  // > 0: the vertical field of view governs instead and the horizontal one follows the
  // screen's aspect (a glTF camera stores its yfov; rendering at another aspect keeps it).
  float vfov_deg = 0;
};

// Where a screen maps into the world: the camera's orthonormal frame and the
// half-extent of the image plane at unit distance.
struct camera_frame {
  glm::vec3 origin, right, up, forward;
  float half_width = 1, half_height = 1;  // tan(hfov/2), scaled by aspect
  int width = 1, height = 1;
  float pixel_angle = 0;  // image-plane size of one pixel at unit distance
};

camera_frame make_frame(const camera& cam, int width, int height);

// The same view: every field equal (a still camera between two frames).
inline bool same_view(const camera& a, const camera& b) {
  return a.position == b.position && a.forward == b.forward && a.up == b.up && a.hfov_deg == b.hfov_deg &&
         a.vfov_deg == b.vfov_deg;
}

// Direction (unit) through screen position (sx, sy) in pixels; (0, 0) is the
// top-left corner of the top-left pixel, y grows downwards.
glm::vec3 ray_direction(const camera_frame& f, float sx, float sy);

// Screen position of a world point, and its distance along forward (<= 0: behind).
glm::vec2 project(const camera_frame& f, const glm::vec3& world, float* depth = nullptr);

// A camera that looks at `target` from `eye`.
camera look_at(const glm::vec3& eye, const glm::vec3& target, float hfov_deg, const glm::vec3& up = {0, 1, 0});

// A camera moving over time: keys of eye and look-at target (world units) at times in
// milliseconds, non-decreasing, linearly interpolated between them (a recorded path's rows,
// apps/common/camera_path.h reads them from CSV).
struct camera_path {
  struct key { double t, eye[3], target[3]; };
  std::vector<key> keys;  // at least one
  // The camera at t_ms (clamped to the path's ends): `base` moved to the eye and turned to
  // the target, its field of view and up kept.
  camera at(double t_ms, const camera& base) const;
};

}  // namespace fov
