// A recorded camera path's file: CSV "t_ms,x,y,z,tx,ty,tz" (eye and look-at target, world
// units), read into fov::camera_path (fov/camera.h), which interpolates between its rows.
#pragma once

#include <string>

#include "fov/camera.h"

namespace fov {

// Throws std::runtime_error "FILE:LINE: reason" for a bad header, bad numbers, an eye or
// target that fails world_point_problem (fov/camera.h), time going backwards or an eye on
// its target.
camera_path load_camera_path(const std::string& path);

}  // namespace fov
