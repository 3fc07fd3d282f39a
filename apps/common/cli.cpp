#include "cli.h"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace fov {

bool parse_gaze(const std::string& text, const display_geometry& d, double xy[2]) {
  if (text == "centre" || text == "center") { xy[0] = 0.5 * d.width; xy[1] = 0.5 * d.height; return true; }
  if (text == "corner") { xy[0] = d.width; xy[1] = d.height; return true; }
  char* end = nullptr;
  xy[0] = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != ',') return false;
  const char* second = end + 1;
  xy[1] = std::strtod(second, &end);
  return end != second && *end == '\0' && std::isfinite(xy[0]) && std::isfinite(xy[1]);
}

void require_gaze(const std::string& flag, const std::string& text, const display_geometry& d, double xy[2]) {
  if (!parse_gaze(text, d, xy))
    throw usage_error(fmt::format("{}: expected X,Y in screen pixels, 'centre' or 'corner' (got '{}')", flag, text));
  if (xy[0] < 0 || xy[0] > d.width || xy[1] < 0 || xy[1] > d.height)
    throw usage_error(fmt::format("{} {} lies outside the {}x{} screen", flag, text, d.width, d.height));
}

}  // namespace fov
