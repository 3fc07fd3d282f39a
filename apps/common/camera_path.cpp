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

}  // namespace fov
