// A recorded camera path: CSV "t_ms,x,y,z,tx,ty,tz" (eye and look-at target, world units),
// replayed in real time with linear interpolation between rows.
#pragma once

#include <string>
#include <vector>

#include "fov/camera.h"

namespace fov {

struct camera_path {
  struct key { double t, eye[3], target[3]; };
  std::vector<key> keys;
  // The camera at t_ms (clamped to the path's ends): `base` moved to the eye and turned to
  // the target, its field of view and up kept.
  camera at(double t_ms, const camera& base) const;
};

// Throws std::runtime_error "FILE:LINE: reason" for a bad header, bad numbers, an eye or
// target that fails world_point_problem (fov/camera.h), time going backwards or an eye on
// its target.
camera_path load_camera_path(const std::string& path);

}  // namespace fov
