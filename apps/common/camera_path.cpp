#include "camera_path.h"

#include "numeric_csv.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace fov {

camera_path load_camera_path(const std::string& path) {
  const numeric_csv csv = read_numeric_csv(path, {"t_ms,x,y,z,tx,ty,tz"}, "t_ms,x,y,z,tx,ty,tz", "camera path");
  camera_path out;
  for (size_t i = 0; i < csv.rows.size(); ++i) {
    const std::vector<double>& v = csv.rows[i];
    if (!out.keys.empty() && v[0] < out.keys.back().t)
      throw std::runtime_error(fmt::format("{}:{}: time goes backwards", path, csv.lines[i]));
    for (int c : {1, 4})
      if (const std::string why = world_point_problem(v[c], v[c + 1], v[c + 2]); !why.empty())
        throw std::runtime_error(fmt::format("{}:{}: the {}: {}", path, csv.lines[i], c == 1 ? "eye" : "target", why));
    if (float(v[1]) == float(v[4]) && float(v[2]) == float(v[5]) && float(v[3]) == float(v[6]))
      throw std::runtime_error(fmt::format("{}:{}: the eye is on its target", path, csv.lines[i]));
    out.keys.push_back({v[0], {v[1], v[2], v[3]}, {v[4], v[5], v[6]}});
  }
  if (out.keys.empty()) throw std::runtime_error(fmt::format("{}: no camera keys", path));
  return out;
}

camera camera_path::at(double t, const camera& base) const {
  size_t i = 0;
  while (i + 1 < keys.size() && keys[i + 1].t <= t) ++i;
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
