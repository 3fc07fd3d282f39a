#include "jod_validation.h"

#include <cmath>
#include <map>
#include <cstdio>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "fov/files.h"
#include "fov/fvvdp.h"
#include "image_io.h"

namespace fov {

namespace {

using json = nlohmann::json;

// A video row's test: "PATH-NN.png (frames A-B, F fps)" (NN the two-digit frame number).
struct clip_spec {
  std::string stem;  // PATH
  int first = 0, last = 0;
  double fps = 0;
};
bool parse_clip(const std::string& text, clip_spec& out) {
  const std::string marker = "-NN.png (frames ";
  const size_t at = text.find(marker);
  if (at == std::string::npos || at == 0) return false;
  out.stem = text.substr(0, at);
  const std::string rest = text.substr(at + marker.size());
  char tail[8] = {};
  int used = 0;
  if (std::sscanf(rest.c_str(), "%d-%d, %lf fps%7s%n", &out.first, &out.last, &out.fps, tail, &used) != 4) return false;
  return std::string(tail) == ")" && size_t(used) == rest.size() && out.first >= 0 && out.first <= out.last && out.last <= 99;
}
// A video row's reference: "PATH.png (static)".
bool parse_still(const std::string& text, std::string& path) {
  const std::string suffix = " (static)";
  if (text.size() <= suffix.size() || text.compare(text.size() - suffix.size(), suffix.size(), suffix) != 0) return false;
  path = text.substr(0, text.size() - suffix.size());
  return true;
}

// The fixations of the folder's foveated columns (its README).
gaze_point fixation(const std::string& view, const display_geometry& d) {
  if (view == "foveated_corner") return {48, 48};
  return screen_centre(d);
}

}  // namespace

jod_validation validate_jod(const std::string& dir) {
  const std::string index = dir + "/jod-reference.json";
  json j;
  try {
    j = json::parse(read_input_file(index, 1 << 20, "JOD reference table"));
    const json& g = j.at("geometry");
    const display_geometry images{g.at("resolution").at(0).get<int>(), g.at("resolution").at(1).get<int>(),
                                  g.at("viewing_distance_screen_widths").get<double>()};
    // Videos: the same pixel pitch and distance on a smaller screen.
    display_geometry video{g.at("video_resolution").at(0).get<int>(), g.at("video_resolution").at(1).get<int>(), 0};
    video.viewing_distance = images.viewing_distance * images.width / video.width;
    jod_validation v;
    for (const json& row : j.at("rows")) {
      const std::string test = row.at("test"), reference = row.at("reference");
      clip_spec clip;
      const bool is_video = parse_clip(test, clip);
      std::map<std::string, fvvdp_result> cached;  // per fixation
      std::pair<frame, frame> pair;
      for (const char* view : {"nonfoveated", "foveated_centre", "foveated_corner"}) {
        const std::string key = std::string("jod_") + view;
        if (!row.contains(key)) continue;
        jod_check c{test, reference, view, row.at(key).get<double>(), 0};
        fvvdp_result q;
        if (!is_video) {
          // The centre's comparison gives the non-foveated value too.
          const std::string& seen = c.view == "foveated_corner" ? c.view : std::string("foveated_centre");
          if (!cached.count(seen)) {
            if (pair.first.rgb.empty()) pair = {read_frame(dir + "/" + test), read_frame(dir + "/" + reference)};
            cached[seen] = fvvdp_image(pair.first, pair.second, images, fixation(seen, images));
          }
          q = cached[seen];
        } else {
          std::string still;
          if (!parse_still(reference, still)) throw file_error(index + ": a video row's reference is not \"PATH.png (static)\"");
          const frame ref = read_frame(dir + "/" + still);
          fvvdp metric(video, clip.fps);
          for (int f = clip.first; f <= clip.last; ++f)
            metric.add(read_frame(fmt::format("{}/{}-{:02d}.png", dir, clip.stem, f)), ref, fixation(view, video));
          q = metric.result();
        }
        c.ours = c.view == "nonfoveated" ? q.jod_nonfoveated : q.jod;
        v.worst = std::max(v.worst, std::abs(c.ours - c.published));
        v.rows.push_back(c);
      }
    }
    if (v.rows.empty()) throw file_error(index + ": no rows with a JOD value");
    return v;
  } catch (const json::exception& e) {
    throw file_error(index + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw file_error(index + ": " + e.what());
  } catch (const std::out_of_range& e) {
    throw file_error(index + ": " + e.what());
  }
}

std::string jod_validation_markdown(const jod_validation& v) {
  std::string s = "| test | reference | view | published | fovray | difference |\n|---|---|---|---:|---:|---:|\n";
  for (const jod_check& c : v.rows)
    s += fmt::format("| {} | {} | {} | {:.3f} | {:.3f} | {:+.3f} |\n", c.test, c.reference, c.view, c.published, c.ours,
                     c.ours - c.published);
  s += fmt::format("\n{} values; the largest difference is {:.3f} JOD.\n", v.rows.size(), v.worst);
  return s;
}

}  // namespace fov
