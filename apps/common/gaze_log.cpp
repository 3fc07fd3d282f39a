#include "gaze_log.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "fov/files.h"

namespace fov {

namespace {

constexpr const char* columns =
    "frame,local_ms,x,y,state,landed,onset_x,onset_y,sample_local_ms,tracker_s,confidence,eye,raw_x,raw_y,age_ms,shown_ms";

bool number_of(const std::string& s, double& v) {
  if (s == "nan" || s == "-nan") return v = std::numeric_limits<double>::quiet_NaN(), true;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size() && !std::isinf(v);
}

}  // namespace

std::string gaze_log_header() { return std::string(columns) + "\n"; }

std::string gaze_log_line(const gaze_log_row& r) {
  const gaze_estimate& e = r.estimate;
  // %.17g where the replay must reproduce the value bit for bit (what the frame used).
  return fmt::format("{},{:.17g},{:.17g},{:.17g},{},{},{:.17g},{:.17g},{:.3f},{:.6f},{:.3f},{},{:.3f},{:.3f},{:.3f},{:.3f}\n",
                     r.frame, r.local_ms, e.at.x, e.at.y, label_of(gaze_state_labels, e.state), int(e.landed),
                     e.landed ? e.saccade_onset.x : NAN, e.landed ? e.saccade_onset.y : NAN, r.sample_local_ms,
                     e.newest.tracker_s, e.newest.confidence, label_of(gaze_eye_labels, e.newest.eye), e.newest.x, e.newest.y,
                     e.age_ms, r.shown_ms);
}

std::vector<gaze_log_row> read_gaze_log(const std::string& path) {
  std::istringstream in(read_input_file(path, max_gaze_log_bytes, "gaze log"));
  std::string line;
  std::getline(in, line);
  if (line != columns) throw std::runtime_error(fmt::format("{}:1: not a gaze log (fovview --gaze-log writes: {})", path, columns));
  std::vector<gaze_log_row> out;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::vector<std::string> c;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) c.push_back(cell);
    auto fail = [&](const std::string& why) { return std::runtime_error(fmt::format("{}:{}: {}", path, number, why)); };
    if (c.size() != 16) throw fail(fmt::format("{} cells; a gaze log row has 16", c.size()));
    double v[16];
    for (size_t i : {0, 1, 2, 3, 5, 6, 7, 8, 9, 10, 12, 13, 14, 15})
      if (!number_of(c[i], v[i])) throw fail(fmt::format("'{}' is not a number", printable(c[i], 40)));
    gaze_log_row r;
    if (!(v[0] == double(out.size()))) throw fail(fmt::format("frame {}, expected {}", printable(c[0], 20), out.size()));
    r.frame = out.size();
    r.local_ms = v[1];
    gaze_estimate& e = r.estimate;
    e.at = {v[2], v[3]};
    if (!std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3])) throw fail("local_ms, x and y must be numbers");
    if (!parse_label(gaze_state_labels, c[4], e.state)) throw fail(fmt::format("state '{}' is not one of {}", printable(c[4], 20), label_list(gaze_state_labels)));
    if (c[5] != "0" && c[5] != "1") throw fail("landed must be 0 or 1");
    e.landed = c[5] == "1";
    if (e.landed && !(std::isfinite(v[6]) && std::isfinite(v[7]))) throw fail("a landed saccade needs its onset_x, onset_y");
    e.saccade_onset = {v[6], v[7]};
    r.sample_local_ms = v[8];
    e.has_sample = std::isfinite(v[8]);
    e.newest.tracker_s = v[9], e.newest.confidence = v[10];
    if (!parse_label(gaze_eye_labels, c[11], e.newest.eye)) throw fail(fmt::format("eye '{}' is not one of {}", printable(c[11], 20), label_list(gaze_eye_labels)));
    e.newest.x = v[12], e.newest.y = v[13], e.age_ms = v[14];
    r.shown_ms = v[15];
    out.push_back(r);
  }
  if (out.empty()) throw std::runtime_error(fmt::format("{}: no frames", path));
  return out;
}

}  // namespace fov
