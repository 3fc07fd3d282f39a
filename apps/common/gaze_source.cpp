#include "gaze_source.h"

#include "numeric_csv.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace fov {

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

namespace {

class fixed_source : public gaze_source {
 public:
  fixed_source(int w, int h, double x, double y) : x_(x), y_(y) { width_ = w, height_ = h; }
  gaze_point poll(double) override { return clamped_gaze(x_, y_); }
  std::string name() const override { return "fixed"; }

 private:
  double x_, y_;
};

class trace_source : public gaze_source {
 public:
  trace_source(const std::string& path, int w, int h) : path_(path) {
    width_ = w, height_ = h;
    const numeric_csv csv = read_numeric_csv(path, {"t_ms,x,y", "t_ms,x_norm,y_norm"},
                                             "t_ms,x,y (pixels) or t_ms,x_norm,y_norm (0..1)", "gaze trace");
    const bool normalised = csv.header == 1;
    for (size_t i = 0; i < csv.rows.size(); ++i) {
      const std::vector<double>& v = csv.rows[i];
      if (!samples_.empty() && v[0] < samples_.back().t)
        throw std::runtime_error(fmt::format("{}:{}: time goes backwards ({} after {})", path, csv.lines[i], v[0], samples_.back().t));
      samples_.push_back({v[0], normalised ? v[1] * w : v[1], normalised ? v[2] * h : v[2]});
    }
    if (samples_.empty()) throw std::runtime_error(fmt::format("{}: no gaze samples", path));
  }
  gaze_point poll(double now) override {
    while (next_ + 1 < samples_.size() && samples_[next_ + 1].t <= now) ++next_;
    const sample& s = samples_[next_];
    gaze_point g{s.x, s.y};
    if (next_ != counted_) counted_ = next_, clamp_to_screen(g.x, g.y);  // count each sample once
    else g.x = std::clamp(g.x, 0.0, double(width_)), g.y = std::clamp(g.y, 0.0, double(height_));
    return g;
  }
  std::string name() const override { return "trace " + path_; }

 private:
  struct sample { double t, x, y; };
  std::string path_;
  std::vector<sample> samples_;
  size_t next_ = 0, counted_ = size_t(-1);
};

class udp_source : public gaze_source {
 public:
  udp_source(uint16_t port, int w, int h) : port_(port) {
    width_ = w, height_ = h, x_ = w / 2.0, y_ = h / 2.0;
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
  gaze_point poll(double now) override {
    char buffer[256];
    for (;;) {
      const ssize_t n = ::recv(fd_, buffer, sizeof(buffer) - 1, 0);
      if (n < 0) break;
      double nx = 0, ny = 0;
      if (!parse_gaze_datagram(std::string(buffer, size_t(n)), nx, ny)) {
        ++malformed;
        continue;
      }
      x_ = nx * width_, y_ = ny * height_;
      clamp_to_screen(x_, y_);
      last_ms_ = now;
    }
    return {x_, y_};
  }
  bool silent(double now) const override { return now - last_ms_ > 500; }
  std::string name() const override { return fmt::format("udp 127.0.0.1:{}", port_); }

 private:
  uint16_t port_;
  int fd_ = -1;
  double x_, y_, last_ms_ = -1e30;
};

}  // namespace

bool parse_gaze_datagram(const std::string& text, double& x, double& y) {
  std::stringstream in(text);
  std::string extra;
  if (!(in >> x >> y) || (in >> extra)) return false;
  return std::isfinite(x) && std::isfinite(y);
}

std::unique_ptr<gaze_source> fixed_gaze(int w, int h, double x, double y) { return std::make_unique<fixed_source>(w, h, x, y); }
std::unique_ptr<gaze_source> trace_gaze(const std::string& path, int w, int h) { return std::make_unique<trace_source>(path, w, h); }
std::unique_ptr<gaze_source> udp_gaze(uint16_t port, int w, int h) { return std::make_unique<udp_source>(port, w, h); }

}  // namespace fov
