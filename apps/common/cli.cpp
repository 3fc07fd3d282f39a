#include "cli.h"

#include <malloc.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <cstdlib>

#include <iostream>
#include <new>
#include <sstream>

#include <fmt/format.h>

#include "fov/files.h"

namespace fov {

void keep_frame_buffers_in_heap() {
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

int run_tool(const char* tool, CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  try {
    app.parse(argc, argv);
    return body();
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::ParseError& e) {
    std::cerr << tool << ": " << e.what() << " (see --help)\n";
    return 2;
  } catch (const usage_error& e) {
    std::cerr << tool << ": " << first_line(e.what()) << "\n";
    return 2;
  } catch (const std::bad_alloc&) {  // what no check foresaw: say so plainly, in one line
    std::cerr << tool << ": out of memory (an allocation failed; smaller sizes, or a machine with more memory)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << tool << ": " << first_line(e.what()) << "\n";
    return 1;
  }
}

bool parse_gaze(const std::string& text, const display_geometry& d, gaze_point& out) {
  if (text == "centre" || text == "center") { out = screen_centre(d); return true; }
  if (text == "corner") { out = {double(d.width), double(d.height)}; return true; }
  char* end = nullptr;
  out.x = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != ',') return false;
  const char* second = end + 1;
  out.y = std::strtod(second, &end);
  return end != second && *end == '\0' && std::isfinite(out.x) && std::isfinite(out.y);
}

gaze_point require_gaze(const std::string& flag, const std::string& text, const display_geometry& d) {
  gaze_point g;
  if (!parse_gaze(text, d, g))
    throw usage_error(fmt::format("{}: expected X,Y in screen pixels, 'centre' or 'corner' (got '{}')", flag, text));
  if (g.x < 0 || g.x > d.width || g.y < 0 || g.y > d.height)
    throw usage_error(fmt::format("{} {} lies outside the {}x{} screen", flag, text, d.width, d.height));
  return g;
}

display_geometry require_display(const std::string& flag, const std::string& text, double viewing_distance) {
  display_geometry display;
  if (const std::string why = parse_display(text, display); !why.empty()) throw usage_error(flag + ": " + why);
  if (viewing_distance != 0) {
    if (const std::string why = viewing_distance_problem(viewing_distance); !why.empty())
      throw usage_error("--viewing-distance: " + why);
    display.viewing_distance = viewing_distance;
  }
  return display;
}

std::string display_help() {
  return "The display: a preset (" + display_preset_names() +
         "; docs/displays.md), WxH (seen from one width), WxH@Nppd (N pixels per degree at the centre), WxH@Ndeg "
         "(a horizontal field of view of N degrees) or WxH@V (seen from V widths)";
}

void require_output(const std::string& flag, const std::string& path, const std::vector<std::string>& inputs) {
  if (path.empty()) return;
  try {
    check_writable(path, inputs);
  } catch (const file_error& e) {
    throw usage_error(fmt::format("{} {}", flag, e.what()));
  }
}

void require_output_dir(const std::string& flag, const std::string& dir) {
  namespace fs = std::filesystem;
  // The directory, or the nearest part of its path that exists (the rest is made later,
  // when the tool first writes): it must be a directory this process can write in.
  fs::path at = fs::absolute(dir);
  while (!fs::exists(at) && at.has_parent_path() && at.parent_path() != at) at = at.parent_path();
  if (!fs::is_directory(at))
    throw usage_error(fmt::format("{} {}: {} is not a directory", flag, dir, at == fs::absolute(dir) ? "it" : at.string()));
  if (::access(at.c_str(), W_OK | X_OK) != 0)
    throw usage_error(fmt::format("{} {}: cannot write in {}: {}", flag, dir, at.string(), std::strerror(errno)));
}

}  // namespace fov
