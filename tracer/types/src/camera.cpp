#include "fov/camera.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace fov {

std::string world_point_problem(double x, double y, double z) {
  if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z))) return "not a finite point";
  if (std::fabs(x) > max_world_coordinate || std::fabs(y) > max_world_coordinate || std::fabs(z) > max_world_coordinate)
    return fmt::format("a coordinate beyond +-{:g} world units", max_world_coordinate);
  return "";
}

camera_frame make_frame(const camera& cam, int width, int height) {
  camera_frame f;
  f.origin = cam.position;
  f.forward = glm::normalize(cam.forward);
  glm::vec3 right = glm::cross(f.forward, cam.up);
  if (glm::dot(right, right) < 1e-12f) right = glm::cross(f.forward, glm::vec3(0, 0, 1));
  f.right = glm::normalize(right);
  f.up = glm::cross(f.right, f.forward);
  f.width = width;
  f.height = height;
  if (cam.vfov_deg > 0) {
    f.half_height = std::tan(0.5f * glm::radians(cam.vfov_deg));
    f.half_width = f.half_height * float(width) / float(height);
  } else {
    f.half_width = std::tan(0.5f * glm::radians(cam.hfov_deg));
    f.half_height = f.half_width * float(height) / float(width);
  }
  f.pixel_angle = 2 * f.half_width / float(width);
  return f;
}

glm::vec3 ray_direction(const camera_frame& f, float sx, float sy) {
  const float u = (2 * sx / float(f.width) - 1) * f.half_width;
  const float v = (1 - 2 * sy / float(f.height)) * f.half_height;
  return glm::normalize(f.forward + u * f.right + v * f.up);
}

glm::vec2 project(const camera_frame& f, const glm::vec3& world, float* depth) {
  const glm::vec3 d = world - f.origin;
  const float z = glm::dot(d, f.forward);
  if (depth) *depth = z;
  const float u = glm::dot(d, f.right) / z, v = glm::dot(d, f.up) / z;
  return {(u / f.half_width + 1) * 0.5f * float(f.width), (1 - v / f.half_height) * 0.5f * float(f.height)};
}

camera look_at(const glm::vec3& eye, const glm::vec3& target, float hfov_deg, const glm::vec3& up) {
  camera c;
  c.position = eye;
  c.forward = glm::normalize(target - eye);
  c.up = up;
  c.hfov_deg = hfov_deg;
  return c;
}

camera camera_path::at(double t, const camera& base) const {
  // The last key at or before t (the first when t precedes them), and the next.
  const auto after = std::upper_bound(keys.begin() + 1, keys.end(), t, [](double v, const key& k) { return v < k.t; });
  const size_t i = size_t(after - keys.begin()) - 1;
  const key& a = keys[i];
  const key& b = keys[std::min(i + 1, keys.size() - 1)];
  const double f = b.t > a.t ? std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0) : 0.0;
  glm::vec3 eye, target;
  for (int c = 0; c < 3; ++c) {
    eye[c] = float(a.eye[c] + f * (b.eye[c] - a.eye[c]));
    target[c] = float(a.target[c] + f * (b.target[c] - a.target[c]));
  }
  camera c = base;  // its field of view and up
  c.position = eye;
  // Between two keys the eye may pass through the target: there the view keeps the nearer
  // key's direction (each key's eye is off its target).
  const glm::vec3 to = target - eye;
  if (glm::dot(to, to) > 0 && std::isfinite(glm::dot(to, to))) {
    c.forward = glm::normalize(to);
  } else {
    const key& k = f < 0.5 ? a : b;
    c.forward = glm::normalize(glm::vec3(float(k.target[0] - k.eye[0]), float(k.target[1] - k.eye[1]), float(k.target[2] - k.eye[2])));
  }
  return c;
}

}  // namespace fov
