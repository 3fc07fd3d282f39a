#include "gaze_source.h"

#include "numeric_csv.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "fov/files.h"
#include <opencv2/calib3d.hpp>

namespace fov {

double gaze_clock_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void gaze_source::clamp_to_screen(double& x, double& y) {
  if (!std::isfinite(x) || !std::isfinite(y)) {
    ++clamped;
    x = width_ / 2.0, y = height_ / 2.0;
    return;
  }
  const double cx = std::clamp(x, 0.0, double(width_)), cy = std::clamp(y, 0.0, double(height_));
  if (cx != x || cy != y) ++clamped;
  x = cx, y = cy;
}

gaze_point gaze_source::poll(double now_ms) {
  std::vector<gaze_sample> fresh;
  read(now_ms, fresh);
  if (!fresh.empty()) last_ = {fresh.back().x, fresh.back().y}, have_last_ = true;
  if (!have_last_) return {width_ / 2.0, height_ / 2.0};
  return last_;
}

void tracker_clock::sync(double tracker_s, double send_ms, double receive_ms) {
  if (!std::isfinite(tracker_s) || receive_ms < send_ms) return;
  // The answer was taken between send and receive: assume half way.
  offset_ms_ = 0.5 * (send_ms + receive_ms) - tracker_s * 1000;
  allowance_ms_ = 0.5 * (receive_ms - send_ms) + 2;
  have_offset_ = from_sync_ = true;
  wants_sync = false;
}

double tracker_clock::to_local(double tracker_s, double arrival_ms) {
  if (!std::isfinite(tracker_s)) return arrival_ms;
  const double anchored = arrival_ms - tracker_s * 1000;  // the offset if it arrived at once
  if (!have_offset_) {
    offset_ms_ = anchored, have_offset_ = true, from_sync_ = false;
    return arrival_ms;
  }
  const double local = tracker_s * 1000 + offset_ms_;
  const double future_ms = local - arrival_ms;
  if (future_ms > std::max(50.0, allowance_ms_) || -future_ms > max_age_ms_) {  // a clock jumped
    ++jumps;
    offset_ms_ = anchored, from_sync_ = false, wants_sync = true;
    return arrival_ms;
  }
  if (future_ms > 0) {
    // Without a sync the smallest delay seen so far is the best estimate: take it.
    if (!from_sync_) offset_ms_ = anchored;
    return arrival_ms;
  }
  return local;
}

namespace {

// A whole, finite number: all of `text`.
bool number(const std::string& text, double& v) {
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size() && std::isfinite(v);
}

// Rows recorded with their times, replayed in real time from the first read: every row
// whose time has come, once; the first row at once. After the last row the gaze stays.
class replay_source : public gaze_source {
 public:
  void read(double now, std::vector<gaze_sample>& out) override {
    if (!std::isfinite(start_)) start_ = now - rows_.front().t;
    for (; next_ < rows_.size() && (next_ == 0 || rows_[next_].t <= now - start_); ++next_) {
      emit(rows_[next_].x, rows_[next_].y, start_ + rows_[next_].t, out);
      out.back().confidence = rows_[next_].confidence;
    }
  }

 protected:
  struct row { double t, x, y, confidence = 1; };
  std::vector<row> rows_;

 private:
  size_t next_ = 0;
  double start_ = std::numeric_limits<double>::quiet_NaN();
};

class fixed_source : public gaze_source {
 public:
  fixed_source(int w, int h, double x, double y) : x_(x), y_(y) { width_ = w, height_ = h; }
  void read(double now, std::vector<gaze_sample>& out) override { emit(x_, y_, now, out); }
  std::string name() const override { return "fixed"; }

 private:
  double x_, y_;
};

class trace_source : public replay_source {
 public:
  trace_source(const std::string& path, int w, int h) : path_(path) {
    width_ = w, height_ = h;
    const numeric_csv csv = read_numeric_csv(path, {"t_ms,x,y", "t_ms,x_norm,y_norm"},
                                             "t_ms,x,y (pixels) or t_ms,x_norm,y_norm (0..1)", "gaze trace");
    const bool normalised = csv.header == 1;
    for (size_t i = 0; i < csv.rows.size(); ++i) {
      const std::vector<double>& v = csv.rows[i];
      if (!rows_.empty() && v[0] < rows_.back().t)
        throw std::runtime_error(fmt::format("{}:{}: time goes backwards ({} after {})", path, csv.lines[i], v[0], rows_.back().t));
      rows_.push_back({v[0], normalised ? v[1] * w : v[1], normalised ? v[2] * h : v[2]});
    }
    if (rows_.empty()) throw std::runtime_error(fmt::format("{}: no gaze samples", path));
  }
  std::string name() const override { return "trace " + path_; }

 private:
  std::string path_;
};

// A trace whose rows were read from another tool's export.
class table_source : public replay_source {
 public:
  table_source(const std::string& path, const trace_columns& c, int w, int h) : path_(path) {
    width_ = w, height_ = h;
    std::istringstream in(read_input_file(path, max_gaze_table_bytes, "gaze export"));
    std::string line;
    if (!std::getline(in, line)) throw std::runtime_error(fmt::format("{}: empty", path));
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte-order mark (Tobii Pro Lab writes one)
    const char delimiter = line.find('\t') != std::string::npos ? '\t' : ',';
    const std::vector<std::string> names = cells(line, delimiter);
    auto column = [&](const std::string& name) -> size_t {
      for (size_t i = 0; i < names.size(); ++i)
        if (names[i] == name) return i;
      std::string have;
      for (size_t i = 0; i < names.size() && i < 12; ++i) have += (i ? ", " : "") + printable(names[i], 40);
      throw std::runtime_error(fmt::format("{}:1: no column '{}' (the header has: {}{})", path, printable(name, 60), have,
                                           names.size() > 12 ? ", ..." : ""));
    };
    const size_t ti = column(c.time), xi = column(c.x), yi = column(c.y);
    const size_t ci = c.confidence.empty() ? size_t(-1) : column(c.confidence);
    double first = std::numeric_limits<double>::quiet_NaN();
    for (int line_no = 2; std::getline(in, line); ++line_no) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty()) continue;
      const std::vector<std::string> v = cells(line, delimiter);
      double t, x, y, conf = 1;
      if (ti >= v.size() || !number(v[ti], t))
        throw std::runtime_error(fmt::format("{}:{}: the time '{}' is not a number", path, line_no,
                                             printable(ti < v.size() ? v[ti] : "", 40)));
      if (xi >= v.size() || yi >= v.size() || !number(v[xi], x) || !number(v[yi], y) ||
          (ci != size_t(-1) && (ci >= v.size() || !number(v[ci], conf) || conf < 0 || conf > 1))) {
        refuse(fmt::format("line {}: no gaze position", line_no));  // a lost sample
        continue;
      }
      t *= c.ms_per_unit;
      if (!std::isfinite(first)) first = t;
      t -= first;
      if (!rows_.empty() && t < rows_.back().t)
        throw std::runtime_error(fmt::format("{}:{}: time goes backwards", path, line_no));
      if (c.coords == trace_coords::normalised) x *= w, y *= h;
      if (c.coords == trace_coords::normalised_bottom_left) x *= w, y = (1 - y) * h;
      rows_.push_back({t, x, y, conf});
    }
    if (rows_.empty()) throw std::runtime_error(fmt::format("{}: no gaze samples (every row lacks a position)", path));
  }
  std::string name() const override { return "export " + path_; }

 private:
  std::string path_;

  static std::vector<std::string> cells(const std::string& line, char delimiter) {
    std::vector<std::string> out;
    std::string cur;
    std::stringstream in(line);
    while (std::getline(in, cur, delimiter)) {
      if (cur.size() >= 2 && cur.front() == '"' && cur.back() == '"') cur = cur.substr(1, cur.size() - 2);
      out.push_back(cur);
    }
    if (!line.empty() && line.back() == delimiter) out.emplace_back();
    return out;
  }
};

class udp_source : public gaze_source {
 public:
  udp_source(uint16_t port, int w, int h, const gaze_calibration& c) : port_(port), calibration_(c) {
    width_ = w, height_ = h;
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw std::runtime_error(fmt::format("--gaze-udp {}: cannot open a socket: {}", port, std::strerror(errno)));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
      const std::string why = std::strerror(errno);
      ::close(fd_);
      throw std::runtime_error(fmt::format("--gaze-udp {}: cannot bind 127.0.0.1:{}: {}", port, port, why));
    }
  }
  ~udp_source() override { ::close(fd_); }
  // Every datagram waiting, stamped with the time of this read (datagrams are read once per
  // frame) or, for version 2, with the sender's time mapped by the smallest delay seen.
  void read(double now, std::vector<gaze_sample>& out) override {
    char buffer[256];
    for (;;) {
      const ssize_t n = ::recv(fd_, buffer, sizeof(buffer), 0);
      if (n < 0) break;
      gaze_datagram d;
      if (n == ssize_t(sizeof(buffer))) {
        refuse("a datagram longer than 255 bytes");
        continue;
      }
      if (const std::string why = parse_gaze_datagram(std::string(buffer, size_t(n)), d); !why.empty()) {
        refuse(why);
        continue;
      }
      if (!calibration_.apply(d.x, d.y)) {
        refuse("the calibration maps the position to infinity");
        continue;
      }
      gaze_sample s;
      s.x = d.x * width_, s.y = d.y * height_;
      s.tracker_s = d.t_s, s.confidence = d.confidence, s.eye = d.eye;
      s.t_ms = clock_.to_local(d.t_s, now);
      clock_jumps = clock_.jumps;
      clamp_to_screen(s.x, s.y);
      ++samples;
      out.push_back(s);
    }
  }
  bool live() const override { return true; }
  std::string name() const override { return fmt::format("udp 127.0.0.1:{}", port_); }

 private:
  uint16_t port_;
  gaze_calibration calibration_;
  int fd_ = -1;
  tracker_clock clock_;
};

// The fields of a datagram: split at spaces, tabs, newlines and commas.
std::vector<std::string> fields(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : text) {
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',') {
      if (!cur.empty()) out.push_back(cur), cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

}  // namespace

void gaze_source::emit(double x, double y, double t_ms, std::vector<gaze_sample>& out) {
  gaze_sample s;
  s.x = x, s.y = y, s.t_ms = t_ms;
  clamp_to_screen(s.x, s.y);
  ++samples;
  out.push_back(s);
}

std::string parse_gaze_datagram(const std::string& text, gaze_datagram& out) {
  if (text.find('\0') != std::string::npos) return "a NUL byte in a datagram";
  const std::vector<std::string> f = fields(text);
  gaze_datagram d;
  size_t at = 0;
  if (!f.empty() && f[0] == "v2") {
    if (f.size() != 6) return fmt::format("version 2 needs 'v2 T C EYE X Y' (6 fields), got {}", f.size());
    if (!number(f[1], d.t_s)) return fmt::format("version 2: time '{}' is not a number", printable(f[1], 32));
    if (!number(f[2], d.confidence) || d.confidence < 0 || d.confidence > 1)
      return fmt::format("version 2: confidence '{}' is not a number in 0..1", printable(f[2], 32));
    const std::string& e = f[3];
    if (e == "l" || e == "L") d.eye = gaze_eye::left;
    else if (e == "r" || e == "R") d.eye = gaze_eye::right;
    else if (e == "b" || e == "B") d.eye = gaze_eye::both;
    else return fmt::format("version 2: eye '{}' is not l, r or b", printable(e, 32));
    at = 4;
  } else if (f.size() != 2) {
    return f.empty() ? "an empty datagram"
                     : fmt::format("expected 'X Y' (version 1) or 'v2 T C EYE X Y', got {} fields", f.size());
  }
  if (!number(f[at], d.x) || !number(f[at + 1], d.y))
    return fmt::format("position '{} {}' is not two numbers", printable(f[at], 32), printable(f[at + 1], 32));
  out = d;
  return "";
}

std::unique_ptr<gaze_source> fixed_gaze(int w, int h, double x, double y) { return std::make_unique<fixed_source>(w, h, x, y); }
std::unique_ptr<gaze_source> trace_gaze(const std::string& path, int w, int h) { return std::make_unique<trace_source>(path, w, h); }
std::unique_ptr<gaze_source> table_gaze(const std::string& path, const trace_columns& c, int w, int h) {
  return std::make_unique<table_source>(path, c, w, h);
}

std::string parse_trace_columns(const std::string& spec, trace_columns& out) {
  trace_columns c;
  if (spec == "pupil") {
    c.time = "gaze_timestamp", c.x = "norm_pos_x", c.y = "norm_pos_y", c.confidence = "confidence";
    c.ms_per_unit = 1000, c.coords = trace_coords::normalised_bottom_left;
    out = c;
    return "";
  }
  std::vector<std::string> parts;
  std::stringstream in(spec);
  for (std::string part; std::getline(in, part, ';');) parts.push_back(part);
  if (parts.empty()) return "expected pupil or TIME,X,Y[,CONFIDENCE][;time=ms|s|us][;coords=pixels|norm|norm-bottom-left]";
  std::vector<std::string> names;
  std::stringstream cols(parts[0]);
  for (std::string n; std::getline(cols, n, ',');) names.push_back(n);
  if (names.size() < 3 || names.size() > 4 || std::any_of(names.begin(), names.end(), [](const std::string& n) { return n.empty(); }))
    return fmt::format("'{}': name 3 or 4 columns, TIME,X,Y[,CONFIDENCE]", printable(parts[0], 80));
  c.time = names[0], c.x = names[1], c.y = names[2], c.confidence = names.size() == 4 ? names[3] : "";
  for (size_t i = 1; i < parts.size(); ++i) {
    const std::string& o = parts[i];
    if (o == "time=ms") c.ms_per_unit = 1;
    else if (o == "time=s") c.ms_per_unit = 1000;
    else if (o == "time=us") c.ms_per_unit = 0.001;
    else if (o == "coords=pixels") c.coords = trace_coords::pixels;
    else if (o == "coords=norm") c.coords = trace_coords::normalised;
    else if (o == "coords=norm-bottom-left") c.coords = trace_coords::normalised_bottom_left;
    else return fmt::format("'{}': options are time=ms|s|us and coords=pixels|norm|norm-bottom-left", printable(o, 60));
  }
  out = c;
  return "";
}
std::unique_ptr<gaze_source> udp_gaze(uint16_t port, int w, int h, const gaze_calibration& c) {
  return std::make_unique<udp_source>(port, w, h, c);
}

bool gaze_calibration::apply(double& x, double& y) const {
  const double w = h[6] * x + h[7] * y + h[8];
  if (!(std::fabs(w) > 1e-12)) return false;
  const double nx = (h[0] * x + h[1] * y + h[2]) / w, ny = (h[3] * x + h[4] * y + h[5]) / w;
  if (!std::isfinite(nx) || !std::isfinite(ny)) return false;
  x = nx, y = ny;
  return true;
}

gaze_calibration read_gaze_calibration(const std::string& path) {
  const std::string text = read_input_file(path, 1u << 20, "calibration");  // a FIFO or a directory refused
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    throw std::runtime_error(fmt::format("{}: not JSON", path));
  }
  auto fail = [&](const std::string& why) { return std::runtime_error(fmt::format("{}: {}", path, why)); };
  auto numbers = [&](const nlohmann::json& v, size_t n, const char* what) {
    std::vector<double> out;
    if (!v.is_array() || v.size() != n) throw fail(fmt::format("{} must be {} numbers", what, n));
    for (const auto& e : v) {
      if (!e.is_number() || !std::isfinite(e.get<double>())) throw fail(fmt::format("{} must be {} finite numbers", what, n));
      out.push_back(e.get<double>());
    }
    return out;
  };
  if (!j.is_object() || j.size() == 0)
    throw fail("expected an object with \"offset\" and \"scale\", \"homography\" or \"grid\"");
  gaze_calibration c;
  c.from = path;
  const bool affine = j.contains("offset") || j.contains("scale");
  if (affine + j.contains("homography") + j.contains("grid") != 1)
    throw fail("give one of \"offset\"/\"scale\", \"homography\" or \"grid\"");
  for (const auto& [key, value] : j.items())
    if (key != "offset" && key != "scale" && key != "homography" && key != "grid" && key != "comment")
      throw fail(fmt::format("unknown key \"{}\"", key.substr(0, 40)));
  if (affine) {
    const std::vector<double> o = j.contains("offset") ? numbers(j["offset"], 2, "\"offset\"") : std::vector<double>{0, 0};
    const std::vector<double> s = j.contains("scale") ? numbers(j["scale"], 2, "\"scale\"") : std::vector<double>{1, 1};
    if (s[0] == 0 || s[1] == 0) throw fail("a \"scale\" of 0 maps every gaze to one line");
    const double h[9] = {s[0], 0, o[0], 0, s[1], o[1], 0, 0, 1};
    std::copy(h, h + 9, c.h);
  } else if (j.contains("homography")) {
    const std::vector<double> h = numbers(j["homography"], 9, "\"homography\"");
    std::copy(h.begin(), h.end(), c.h);
  } else {
    const nlohmann::json& g = j["grid"];
    if (!g.is_array() || g.size() < 4 || g.size() > 1000) throw fail("\"grid\" must list 4 to 1000 targets [TX, TY, SX, SY]");
    std::vector<cv::Point2d> tracker, screen;
    for (const auto& row : g) {
      const std::vector<double> v = numbers(row, 4, "each \"grid\" target");
      tracker.emplace_back(v[0], v[1]), screen.emplace_back(v[2], v[3]);
    }
    // All targets (or all tracker positions) on one line fix no homography, whatever
    // OpenCV returns for them: the spread's smaller principal axis must not vanish.
    auto flat = [](const std::vector<cv::Point2d>& pts) {
      double mx = 0, my = 0;
      for (const auto& q : pts) mx += q.x, my += q.y;
      mx /= double(pts.size()), my /= double(pts.size());
      double xx = 0, yy = 0, xy = 0;
      for (const auto& q : pts) xx += (q.x - mx) * (q.x - mx), yy += (q.y - my) * (q.y - my), xy += (q.x - mx) * (q.y - my);
      const double tr = xx + yy, det = xx * yy - xy * xy;
      const double small = 0.5 * tr - std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
      return !(small > 1e-8 * std::max(tr, 1e-300));
    };
    if (flat(tracker) || flat(screen)) throw fail("the grid's targets do not fix a mapping (collinear or repeated points)");
    cv::Mat h;
    try {
      h = cv::findHomography(tracker, screen, 0);
    } catch (const cv::Exception&) {
    }
    if (h.empty() || h.rows != 3 || h.cols != 3) throw fail("the grid's targets do not fix a mapping (collinear or repeated points)");
    for (int i = 0; i < 9; ++i) c.h[i] = h.at<double>(i / 3, i % 3);
    double sum = 0;
    for (size_t i = 0; i < tracker.size(); ++i) {
      double x = tracker[i].x, y = tracker[i].y;
      if (!c.apply(x, y)) throw fail("the grid's fit sends a target to infinity");
      sum += (x - screen[i].x) * (x - screen[i].x) + (y - screen[i].y) * (y - screen[i].y);
    }
    c.fit_rms = std::sqrt(sum / double(tracker.size()));
    c.fit_points = tracker.size();
  }
  for (double v : c.h)
    if (!std::isfinite(v)) throw fail("the mapping is not finite");
  double x = 0.5, y = 0.5;
  if (!c.apply(x, y)) throw fail("the mapping sends the screen's centre to infinity");
  return c;
}

}  // namespace fov
