#include "window.h"

#include <sstream>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>

#include "fov/colour.h"
#include "fov/files.h"

namespace fov {

cv::Mat display_image(const frame& f) {
  // sRGB by table: 4096 steps of linear [0, 1] (finer than 8-bit output needs near black
  // only up to 1 code value), in parallel over rows.
  static const std::vector<uint8_t> table = [] {
    std::vector<uint8_t> t(4097);
    for (int i = 0; i <= 4096; ++i) t[size_t(i)] = uint8_t(std::lround(255.0f * srgb_encode(float(i) / 4096.0f)));
    return t;
  }();
  auto byte = [&](float v) { return table[size_t(std::clamp(v, 0.0f, 1.0f) * 4096.0f + 0.5f)]; };
  cv::Mat out(f.height, f.width, CV_8UC3);
  tbb::parallel_for(tbb::blocked_range<int>(0, f.height, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      auto* row = out.ptr<cv::Vec3b>(y);
      const glm::vec3* in = f.rgb.data() + size_t(y) * f.width;
      for (int x = 0; x < f.width; ++x) row[x] = cv::Vec3b(byte(in[x].b), byte(in[x].g), byte(in[x].r));
    }
  });
  return out;
}

std::string display_problem() {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display) {
    if (const char* w = std::getenv("WAYLAND_DISPLAY"); w && *w) return "";  // Qt reaches it, or says why
    return "no display: DISPLAY is not set (run under X11, or xvfb-run for tests)";
  }
  // DISPLAY is [host]:N[.S]. Qt aborts the process (exit 134, several lines) when it cannot
  // reach the server, so the server is tried here first: a local one through its socket,
  // a remote one through TCP port 6000 + N, each within two seconds.
  const std::string text = display;
  const size_t colon = text.rfind(':');
  char* end = nullptr;
  const long number = colon == std::string::npos ? -1 : std::strtol(text.c_str() + colon + 1, &end, 10);
  if (number < 0 || number > 65535 - 6000 || end == text.c_str() + colon + 1)
    return fmt::format("DISPLAY={}: not a display name ([host]:N)", printable(text));
  const std::string host = text.substr(0, colon);
  int fd = -1;
  bool reached = false;
  if (host.empty() || host == "unix" || host.rfind('/', 0) == 0) {
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    const std::string path = host.rfind('/', 0) == 0 ? host : fmt::format("/tmp/.X11-unix/X{}", number);
    for (bool abstract : {true, false}) {  // Linux X servers listen on an abstract socket too
      fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
      std::memset(a.sun_path, 0, sizeof(a.sun_path));
      std::strncpy(a.sun_path + (abstract ? 1 : 0), path.c_str(), sizeof(a.sun_path) - 2);
      const socklen_t len = socklen_t(offsetof(sockaddr_un, sun_path) + (abstract ? 1 : 0) + path.size() + (abstract ? 0 : 1));
      reached = fd >= 0 && ::connect(fd, reinterpret_cast<const sockaddr*>(&a), len) == 0;
      if (fd >= 0) ::close(fd);
      if (reached) break;
    }
  } else {
    addrinfo hints{}, *found = nullptr;
    hints.ai_socktype = SOCK_STREAM;
    if (::getaddrinfo(host.c_str(), std::to_string(6000 + number).c_str(), &hints, &found) == 0) {
      for (addrinfo* ai = found; ai && !reached; ai = ai->ai_next) {
        fd = ::socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK, ai->ai_protocol);
        if (fd < 0) continue;
        if (::connect(fd, ai->ai_addr, ai->ai_addrlen) == 0) {
          reached = true;
        } else if (errno == EINPROGRESS) {
          pollfd p{fd, POLLOUT, 0};
          int error = 0;
          socklen_t n = sizeof(error);
          reached = ::poll(&p, 1, 2000) == 1 && ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &n) == 0 && error == 0;
        }
        ::close(fd);
      }
      ::freeaddrinfo(found);
    }
  }
  if (!reached) return fmt::format("DISPLAY={}: no X server answers there (is it running? xvfb-run for tests)", printable(text));
  return "";
}

view_window::view_window(const std::string& title, int width, int height, presentation how)
    : title_(title), how_(how), frame_(width, height) {
  if (const std::string why = display_problem(); !why.empty()) throw std::runtime_error(why);
  const cv::Size scaled(int(std::lround(width * how.scale)), int(std::lround(height * how.scale)));
  screen_ = scaled;
  if (how.fullscreen) {
    cv::namedWindow(title_, cv::WINDOW_NORMAL | cv::WINDOW_GUI_NORMAL);
    cv::setWindowProperty(title_, cv::WND_PROP_FULLSCREEN, cv::WINDOW_FULLSCREEN);
    cv::imshow(title_, cv::Mat(scaled, CV_8UC3, cv::Scalar(0, 0, 0)));
    cv::waitKey(50);
    const cv::Rect r = cv::getWindowImageRect(title_);
    if (r.width > 0 && r.height > 0) screen_ = r.size();
    offset_ = {(screen_.width - scaled.width) / 2, (screen_.height - scaled.height) / 2};  // negative: the edges are cut
  } else {
    cv::namedWindow(title_, cv::WINDOW_AUTOSIZE | cv::WINDOW_GUI_NORMAL);
    cv::resizeWindow(title_, scaled.width, scaled.height);
  }
  cv::setMouseCallback(title_, &view_window::on_mouse, this);
}

view_window::~view_window() { cv::destroyWindow(title_); }

void view_window::on_mouse(int event, int x, int y, int flags, void* self) {
  auto& m = static_cast<view_window*>(self)->mouse_;
  m.x = x + 0.5, m.y = y + 0.5, m.seen = true;
  if (event == cv::EVENT_RBUTTONDOWN) m.right = true, m.last_x = x, m.last_y = y;
  if (event == cv::EVENT_RBUTTONUP) m.right = false;
  if (m.right && (flags & cv::EVENT_FLAG_RBUTTON)) m.drag_x += x - m.last_x, m.drag_y += y - m.last_y, m.last_x = x, m.last_y = y;
}

void view_window::show(const cv::Mat& bgr) {
  if (how_.scale == 1 && !how_.fullscreen) return cv::imshow(title_, bgr);
  cv::Mat scaled = bgr;
  if (how_.scale != 1) {
    const bool whole = std::fabs(how_.scale - std::round(how_.scale)) < 1e-9;
    cv::resize(bgr, scaled, cv::Size(), how_.scale, how_.scale,
               whole ? cv::INTER_NEAREST : how_.scale < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  }
  if (!how_.fullscreen) return cv::imshow(title_, scaled);
  cv::Mat canvas(screen_, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Rect where = cv::Rect(offset_, scaled.size()) & cv::Rect(cv::Point(0, 0), screen_);
  scaled(cv::Rect(where.tl() - offset_, where.size())).copyTo(canvas(where));
  cv::imshow(title_, canvas);
}
int view_window::key(int wait_ms) { return cv::waitKeyEx(std::max(1, wait_ms)); }

bool view_window::mouse(double& x, double& y) const {
  if (!mouse_.seen) return false;
  x = (mouse_.x - offset_.x) / how_.scale, y = (mouse_.y - offset_.y) / how_.scale;
  return true;
}

bool view_window::right_drag(double& dx, double& dy) {
  dx = mouse_.drag_x, dy = mouse_.drag_y;
  mouse_.drag_x = mouse_.drag_y = 0;
  return dx != 0 || dy != 0;
}

bool view_window::closed() const {
  try {
    return cv::getWindowProperty(title_, cv::WND_PROP_VISIBLE) < 1;
  } catch (const cv::Exception&) {
    return true;
  }
}

fitted_text fit_text(const std::vector<std::string>& lines, int max_width, double max_scale, int thickness) {
  constexpr int font = cv::FONT_HERSHEY_SIMPLEX;
  fitted_text out;
  for (double scale = max_scale;; scale *= 0.9) {
    const bool last = scale * 0.9 < 0.3;
    auto width_of = [&](const std::string& s) { return cv::getTextSize(s, font, scale, thickness, nullptr).width; };
    out.lines.clear();
    out.scale = scale, out.width = 0;
    bool fits = true;
    for (const std::string& line : lines) {
      if (width_of(line) <= max_width) {  // fits: kept as written (its spacing too)
        out.lines.push_back(line);
        continue;
      }
      std::string cur, word;
      std::istringstream words(line);
      bool any = false;
      while (words >> word) {
        const std::string joined = cur.empty() ? word : cur + " " + word;
        if (!cur.empty() && width_of(joined) > max_width) out.lines.push_back(cur), cur = word;
        else cur = joined;
        any = true;
      }
      if (!any || !cur.empty()) out.lines.push_back(cur);
    }
    for (const std::string& l : out.lines) {
      out.width = std::max(out.width, width_of(l));
      if (width_of(l) > max_width) fits = false;
    }
    out.line_height = int(std::lround(36 * scale));
    if (fits || last) return out;
  }
}

cv::Mat message_screen(int width, int height, const std::vector<std::string>& lines) {
  cv::Mat m(height, width, CV_8UC3, cv::Scalar(64, 64, 64));
  const fitted_text t = fit_text(lines, width - width / 4, 0.9, 2);
  const int top = height / 2 - int(t.lines.size()) * t.line_height / 2 + t.line_height / 2;
  for (size_t i = 0; i < t.lines.size(); ++i)
    cv::putText(m, t.lines[i], {width / 8, top + int(i) * t.line_height}, cv::FONT_HERSHEY_SIMPLEX, t.scale, {255, 255, 255},
                2, cv::LINE_AA);
  return m;
}

void draw_overlay(cv::Mat& bgr, const std::vector<std::string>& given, gaze_point gaze) {
  if (given.empty()) return;
  constexpr int font = cv::FONT_HERSHEY_SIMPLEX;
  const fitted_text t = fit_text(given, std::max(16, bgr.cols - 32), 0.5, 1);
  const std::vector<std::string>& lines = t.lines;
  const double scale = t.scale;
  const int width = t.width, line_height = t.line_height;
  const int box_w = width + 16, box_h = int(lines.size()) * line_height + 12;
  // The corner farthest from the gaze.
  const bool right = gaze.x < bgr.cols / 2.0, bottom = gaze.y < bgr.rows / 2.0;
  const int x0 = right ? bgr.cols - box_w - 8 : 8, y0 = bottom ? bgr.rows - box_h - 8 : 8;
  const cv::Rect box = cv::Rect(x0, y0, box_w, box_h) & cv::Rect(0, 0, bgr.cols, bgr.rows);
  cv::Mat roi = bgr(box);
  roi.convertTo(roi, -1, 0.35, 0);  // darken behind the text
  for (size_t i = 0; i < lines.size(); ++i)
    cv::putText(bgr, lines[i], {x0 + 8, y0 + 8 + line_height * int(i + 1) - 4}, font, scale, {255, 255, 255}, 1, cv::LINE_AA);
}

void draw_gaze_cursor(cv::Mat& bgr, gaze_point gaze) {
  const cv::Point c{int(gaze.x), int(gaze.y)};
  cv::circle(bgr, c, 9, {0, 0, 0}, 3, cv::LINE_AA);
  cv::circle(bgr, c, 9, {0, 255, 255}, 1, cv::LINE_AA);
}

}  // namespace fov
