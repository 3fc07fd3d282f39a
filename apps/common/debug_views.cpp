#include "debug_views.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fov {

namespace {

constexpr double pi = 3.14159265358979323846;

glm::vec3 heat(float t) {  // 0 blue .. 0.5 green .. 1 red
  t = std::clamp(t, 0.0f, 1.0f);
  return t < 0.5f ? glm::mix(glm::vec3(0, 0, 1), glm::vec3(0, 1, 0), 2 * t) : glm::mix(glm::vec3(0, 1, 0), glm::vec3(1, 0, 0), 2 * t - 1);
}

}  // namespace

frame debug_overlay(debug_view view, const frame& image, const pointset* set, gaze_point gaze,
                    const refinement_map* map, uint32_t levels) {
  frame out = image;
  const int w = image.width, h = image.height;
  if (view == debug_view::refinement) {
    if (!map) throw std::invalid_argument("--debug-view refinement needs --adaptive (a nested set's refined frame)");
    point_samples placement;  // the map's placement, as screen_to_canvas reads it
    placement.offset = map->offset, placement.mirror_x = map->mirror_x, placement.mirror_y = map->mirror_y;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        uint32_t cx, cy;
        screen_to_canvas(placement, w, h, x, y, cx, cy);
        const float t = levels > 1 ? float(map->at(cx, cy)) / float(levels - 1) : 0.0f;
        glm::vec3& c = out.rgb[size_t(y) * w + x];
        c = 0.5f * glm::clamp(c, 0.0f, 1.0f) + 0.5f * heat(t);
      }
    return out;
  }
  if (view == debug_view::eccentricity) {
    const display_geometry d = set ? set->model.display : display_geometry{w, h, 1.0};
    for (double deg : {5.0, 10.0, 20.0, 30.0, 45.0}) {
      const double r = std::tan(deg * pi / 180) * d.width * d.viewing_distance;
      const int steps = int(2 * pi * r) + 8;
      for (int i = 0; i < steps; ++i) {
        const double a = 2 * pi * i / steps;
        const int x = int(gaze.x + r * std::cos(a)), y = int(gaze.y + r * std::sin(a));
        if (x >= 0 && x < w && y >= 0 && y < h) out.rgb[size_t(y) * w + x] = {1, 0.9f, 0};
      }
    }
    return out;
  }
  if (!set) throw std::invalid_argument(std::string("--debug-view ") + label_of(debug_view_labels, view) + " needs --points");
  const canvas_offset o = offset_for_gaze(set->model.display, gaze);
  if (view == debug_view::points) {
    for (glm::vec3& c : out.rgb) c *= 0.35f;
    for (const point& p : set->points) {
      const int x = int(p.x) - o.x, y = int(p.y) - o.y;
      if (x >= 0 && x < w && y >= 0 && y < h) out.rgb[size_t(y) * w + x] = {1, 1, 1};
    }
    return out;
  }
  {  // density
    // The set's own points per pixel, counted over 8 x 8-pixel blocks, on a log scale.
    const int block = 8, bw = (w + block - 1) / block, bh = (h + block - 1) / block;
    std::vector<int> count(size_t(bw) * bh, 0);
    for (const point& p : set->points) {
      const int x = int(p.x) - o.x, y = int(p.y) - o.y;
      if (x >= 0 && x < w && y >= 0 && y < h) ++count[size_t(y / block) * bw + x / block];
    }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float density = std::max(1e-3f, float(count[size_t(y / block) * bw + x / block]) / (block * block));
        out.rgb[size_t(y) * w + x] = heat((std::log10(density) + 3) / 3.5f);  // 1e-3 .. 3 points per pixel
      }
    return out;
  }
}

}  // namespace fov
