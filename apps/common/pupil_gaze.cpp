#include "pupil_gaze.h"

#include <zmq.h>
#include <msgpack.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <mutex>
#include <regex>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "fov/files.h"

namespace fov {

namespace {

// Checks that a msgpack byte string is one complete object whose containers declare no more
// elements than bytes remain. msgpack-c allocates a container's declared size before reading
// it, so five bytes declaring 2^32 elements would ask for ~100 GB; this keeps its allocations
// within a small multiple of the payload. "" or the reason.
std::string msgpack_bounded(const unsigned char* p, size_t n) {
  size_t at = 0, pending = 1;
  auto need = [&](size_t k) { return n - at >= k; };
  auto be = [&](size_t k) {  // a big-endian length of k bytes at `at`
    uint64_t v = 0;
    for (size_t i = 0; i < k; ++i) v = (v << 8) | p[at + i];
    at += k;
    return v;
  };
  while (pending > 0) {
    if (!need(1)) return "the payload ends inside a msgpack object";
    const unsigned char b = p[at++];
    --pending;
    uint64_t skip = 0, items = 0;
    if (b <= 0x7f || b >= 0xe0 || b == 0xc0 || b == 0xc2 || b == 0xc3) {
    } else if (b >= 0x80 && b <= 0x8f) items = 2 * (b & 0x0f);
    else if (b >= 0x90 && b <= 0x9f) items = b & 0x0f;
    else if (b >= 0xa0 && b <= 0xbf) skip = b & 0x1f;
    else {
      switch (b) {
        case 0xc4: case 0xd9: if (!need(1)) return "truncated"; skip = be(1); break;
        case 0xc5: case 0xda: if (!need(2)) return "truncated"; skip = be(2); break;
        case 0xc6: case 0xdb: if (!need(4)) return "truncated"; skip = be(4); break;
        case 0xc7: if (!need(1)) return "truncated"; skip = be(1) + 1; break;
        case 0xc8: if (!need(2)) return "truncated"; skip = be(2) + 1; break;
        case 0xc9: if (!need(4)) return "truncated"; skip = be(4) + 1; break;
        case 0xca: skip = 4; break;
        case 0xcb: skip = 8; break;
        case 0xcc: case 0xd0: skip = 1; break;
        case 0xcd: case 0xd1: skip = 2; break;
        case 0xce: case 0xd2: skip = 4; break;
        case 0xcf: case 0xd3: skip = 8; break;
        case 0xd4: skip = 2; break;
        case 0xd5: skip = 3; break;
        case 0xd6: skip = 5; break;
        case 0xd7: skip = 9; break;
        case 0xd8: skip = 17; break;
        case 0xdc: if (!need(2)) return "truncated"; items = be(2); break;
        case 0xdd: if (!need(4)) return "truncated"; items = be(4); break;
        case 0xde: if (!need(2)) return "truncated"; items = 2 * be(2); break;
        case 0xdf: if (!need(4)) return "truncated"; items = 2 * be(4); break;
        default: return fmt::format("byte 0x{:02x} starts no msgpack object", b);
      }
    }
    if (skip > n - at) return "the payload ends inside a msgpack object";
    at += size_t(skip);
    if (items > n - at) return "a msgpack container declares more elements than the payload holds";
    pending += size_t(items);
  }
  if (at != n) return fmt::format("{} bytes after the msgpack object", n - at);
  return "";
}

bool as_number(const msgpack_object& o, double& v) {
  switch (o.type) {
    case MSGPACK_OBJECT_FLOAT32:
    case MSGPACK_OBJECT_FLOAT64: v = o.via.f64; break;
    case MSGPACK_OBJECT_POSITIVE_INTEGER: v = double(o.via.u64); break;
    case MSGPACK_OBJECT_NEGATIVE_INTEGER: v = double(o.via.i64); break;
    default: return false;
  }
  return std::isfinite(v);
}

bool key_is(const msgpack_object& k, const char* name) {
  return (k.type == MSGPACK_OBJECT_STR && k.via.str.size == std::strlen(name) &&
          std::memcmp(k.via.str.ptr, name, k.via.str.size) == 0) ||
         (k.type == MSGPACK_OBJECT_BIN && k.via.bin.size == std::strlen(name) &&
          std::memcmp(k.via.bin.ptr, name, k.via.bin.size) == 0);
}

}  // namespace

std::string parse_pupil_endpoint(const std::string& text, std::string& host, uint16_t& port) {
  static const std::regex form(R"(tcp://([A-Za-z0-9.\-]{1,253}|\[[0-9A-Fa-f:.]{2,45}\]):([0-9]{1,5}))");
  std::smatch m;
  if (!std::regex_match(text, m, form)) return "expected tcp://HOST:PORT (Pupil Remote's address; its default port is 50020)";
  const long p = std::strtol(m[2].str().c_str(), nullptr, 10);
  if (p < 1 || p > 65535) return fmt::format("port {} is not in 1..65535", m[2].str());
  host = m[1].str(), port = uint16_t(p);
  return "";
}

namespace {

// The eye a gaze topic names: "gaze.3d.01." both, "gaze.3d.0." eye 0 (Pupil Core's right
// eye), "gaze.3d.1." eye 1; the surface mapper's datum topics end "._on_surface" after it.
gaze_eye eye_of(std::string topic) {
  const std::string suffix = "_on_surface";
  if (topic.size() > suffix.size() && topic.compare(topic.size() - suffix.size(), suffix.size(), suffix) == 0)
    topic.erase(topic.size() - suffix.size());
  if (topic.find(".01.") != std::string::npos) return gaze_eye::both;
  if (topic.size() >= 3 && topic.compare(topic.size() - 3, 3, ".0.") == 0) return gaze_eye::right;
  if (topic.size() >= 3 && topic.compare(topic.size() - 3, 3, ".1.") == 0) return gaze_eye::left;
  return gaze_eye::both;
}

// One gaze datum (a map with norm_pos, confidence, timestamp): "" or why it is malformed.
// In a surface message each datum's own topic names its eye (`eye_from_datum`).
std::string decode_gaze_datum(const msgpack_object& o, pupil_gaze_message& g, bool eye_from_datum) {
  if (o.type != MSGPACK_OBJECT_MAP) return "not a msgpack map";
  bool pos = false, conf = false, stamp = false;
  const msgpack_object_map& map = o.via.map;
  for (uint32_t i = 0; i < map.size; ++i) {
    const msgpack_object &k = map.ptr[i].key, &v = map.ptr[i].val;
    if (key_is(k, "norm_pos")) {
      pos = v.type == MSGPACK_OBJECT_ARRAY && v.via.array.size == 2 && as_number(v.via.array.ptr[0], g.norm_x) &&
            as_number(v.via.array.ptr[1], g.norm_y);
      if (!pos) return "norm_pos is not two finite numbers";
    } else if (key_is(k, "confidence")) {
      if (!(conf = as_number(v, g.confidence))) return "confidence is not a finite number";
    } else if (key_is(k, "timestamp")) {
      if (!(stamp = as_number(v, g.timestamp))) return "timestamp is not a finite number";
    } else if (eye_from_datum && key_is(k, "topic") && v.type == MSGPACK_OBJECT_STR) {
      g.eye = eye_of(std::string(v.via.str.ptr, v.via.str.size));
    }
  }
  if (!(pos && conf && stamp)) return fmt::format("lacks {}", !pos ? "norm_pos" : !conf ? "confidence" : "timestamp");
  g.confidence = std::clamp(g.confidence, 0.0, 1.0);
  return "";
}

}  // namespace

std::string parse_pupil_gaze(const std::string& topic, const unsigned char* payload, size_t size,
                             std::vector<pupil_gaze_message>& out) {
  const bool surface = topic.rfind("surfaces.", 0) == 0;
  if (topic.rfind("gaze.", 0) != 0 && !surface)
    return fmt::format("topic '{}' is not a gaze or surface topic", printable(topic, 40));
  if (const std::string why = msgpack_bounded(payload, size); !why.empty()) return "payload: " + why;
  msgpack_unpacked r;
  msgpack_unpacked_init(&r);
  size_t offset = 0;
  const msgpack_unpack_return ret = msgpack_unpack_next(&r, reinterpret_cast<const char*>(payload), size, &offset);
  std::string problem;
  std::vector<pupil_gaze_message> found;
  if (ret != MSGPACK_UNPACK_SUCCESS) {
    problem = "payload: not msgpack";
  } else if (!surface) {
    pupil_gaze_message g;
    g.eye = eye_of(topic);
    if (const std::string why = decode_gaze_datum(r.data, g, false); !why.empty())
      problem = why == "not a msgpack map" ? "payload: not a msgpack map" : "the payload " + why;
    else found.push_back(g);
  } else if (r.data.type != MSGPACK_OBJECT_MAP) {
    problem = "payload: not a msgpack map";
  } else {  // the surface mapper: gaze_on_surfaces, a list of gaze data in the surface's coordinates
    const msgpack_object_map& map = r.data.via.map;
    bool list = false;
    for (uint32_t i = 0; i < map.size && problem.empty(); ++i) {
      if (!key_is(map.ptr[i].key, "gaze_on_surfaces")) continue;
      const msgpack_object& v = map.ptr[i].val;
      if (v.type != MSGPACK_OBJECT_ARRAY) {
        problem = "gaze_on_surfaces is not a list";
        break;
      }
      list = true;
      for (uint32_t j = 0; j < v.via.array.size && problem.empty(); ++j) {
        pupil_gaze_message g;
        if (const std::string why = decode_gaze_datum(v.via.array.ptr[j], g, true); !why.empty())
          problem = fmt::format("gaze_on_surfaces[{}]: {}", j, why);
        else found.push_back(g);
      }
    }
    if (problem.empty() && !list) problem = "a surface message without gaze_on_surfaces";
  }
  msgpack_unpacked_destroy(&r);
  if (!problem.empty()) return problem;
  out = std::move(found);
  return "";
}

namespace {

class pupil_source : public gaze_source {
 public:
  pupil_source(const pupil_params& p, const gaze_calibration& c, int w, int h) : p_(p), calibration_(c) {
    width_ = w, height_ = h;
    std::string problem = parse_pupil_endpoint(p.endpoint, host_, remote_port_);
    if (!problem.empty()) throw std::runtime_error(fmt::format("--gaze-pupil {}: {}", p.endpoint, problem));
    ctx_ = zmq_ctx_new();
    if (!ctx_) throw std::runtime_error(fmt::format("--gaze-pupil {}: cannot start ZeroMQ", p.endpoint));
    try {
      open_remote(int(p.timeout_ms));
      std::string answer;
      if (!ask("SUB_PORT", answer, nullptr, nullptr))
        fail(fmt::format("no answer from Pupil Remote within {:.0f} ms (is Pupil Capture running, with Pupil Remote on this port?)",
                         p.timeout_ms));
      char* end = nullptr;
      const long sub_port = std::strtol(answer.c_str(), &end, 10);
      if (answer.empty() || *end || sub_port < 1 || sub_port > 65535)
        fail(fmt::format("Pupil Remote answered '{}' to SUB_PORT, not a port: is this Pupil Remote?", printable(answer, 40)));
      sync_clock();
      if (!clock_.synced()) fail("Pupil Remote did not answer 't' with its time: is this Pupil Remote?");
      sub_ = zmq_socket(ctx_, ZMQ_SUB);
      const int64_t max_message = 1 << 20;
      const int zero = 0, hwm = 10000;
      zmq_setsockopt(sub_, ZMQ_MAXMSGSIZE, &max_message, sizeof(max_message));
      zmq_setsockopt(sub_, ZMQ_LINGER, &zero, sizeof(zero));
      zmq_setsockopt(sub_, ZMQ_RCVHWM, &hwm, sizeof(hwm));
      const std::string address = fmt::format("tcp://{}:{}", host_, sub_port);
      if (zmq_connect(sub_, address.c_str()) != 0) fail(fmt::format("cannot connect to {}: {}", address, zmq_strerror(zmq_errno())));
      zmq_setsockopt(sub_, ZMQ_SUBSCRIBE, p.topic.data(), p.topic.size());
      open_remote(200);  // later requests come from the receiving thread: never wait long
    } catch (...) {
      close();
      throw;
    }
    thread_ = std::thread([this] { receive(); });
  }
  ~pupil_source() override {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    close();
  }
  void read(double, std::vector<gaze_sample>& out) override {
    std::lock_guard<std::mutex> lock(mutex_);
    for (gaze_sample& s : queue_) {
      clamp_to_screen(s.x, s.y);
      out.push_back(s);
    }
    samples += queue_.size();
    queue_.clear();
    malformed = malformed_, clock_jumps = jumps_;
    if (!problem_.empty()) last_problem = problem_;
  }
  bool live() const override { return true; }
  std::string name() const override { return "pupil " + p_.endpoint; }

 private:
  [[noreturn]] void fail(const std::string& why) {
    throw std::runtime_error(fmt::format("--gaze-pupil {}: {}", p_.endpoint, why));
  }
  void open_remote(int timeout_ms) {
    if (req_) zmq_close(req_);
    req_ = zmq_socket(ctx_, ZMQ_REQ);
    const int zero = 0, one = 1;
    const int64_t max_message = 4096;
    zmq_setsockopt(req_, ZMQ_LINGER, &zero, sizeof(zero));
    zmq_setsockopt(req_, ZMQ_RCVTIMEO, &timeout_ms, sizeof(timeout_ms));
    zmq_setsockopt(req_, ZMQ_SNDTIMEO, &timeout_ms, sizeof(timeout_ms));
    zmq_setsockopt(req_, ZMQ_REQ_RELAXED, &one, sizeof(one));  // a new request after a lost answer
    zmq_setsockopt(req_, ZMQ_REQ_CORRELATE, &one, sizeof(one));
    zmq_setsockopt(req_, ZMQ_MAXMSGSIZE, &max_message, sizeof(max_message));
    const std::string address = fmt::format("tcp://{}:{}", host_, remote_port_);
    if (zmq_connect(req_, address.c_str()) != 0) fail(fmt::format("cannot connect: {}", zmq_strerror(zmq_errno())));
  }
  // One request, one answer (a single frame); false on a timeout.
  bool ask(const std::string& request, std::string& answer, double* send_ms, double* receive_ms) {
    const double sent = gaze_clock_ms();
    if (zmq_send(req_, request.data(), request.size(), 0) < 0) return false;
    char buffer[256];
    const int n = zmq_recv(req_, buffer, sizeof(buffer), 0);
    const double received = gaze_clock_ms();
    if (n < 0) return false;
    int more = 0;
    size_t more_size = sizeof(more);
    zmq_getsockopt(req_, ZMQ_RCVMORE, &more, &more_size);
    bool extra = false;
    while (more) {  // drain extra frames: not an answer Pupil Remote gives
      extra = true;
      if (zmq_recv(req_, buffer, sizeof(buffer), 0) < 0) break;
      zmq_getsockopt(req_, ZMQ_RCVMORE, &more, &more_size);
    }
    answer = extra ? std::string("(several frames)") : std::string(buffer, size_t(std::min<int>(n, int(sizeof(buffer)))));
    if (send_ms) *send_ms = sent;
    if (receive_ms) *receive_ms = received;
    return true;
  }
  // Asks for Pupil's clock ("t"); on an answer that is not a number nothing changes.
  bool sync_clock() {
    std::string answer;
    double sent = 0, received = 0;
    if (!ask("t", answer, &sent, &received)) return false;
    char* end = nullptr;
    const double t = std::strtod(answer.c_str(), &end);
    if (answer.empty() || *end || !std::isfinite(t)) return false;
    clock_.sync(t, sent, received);
    return true;
  }
  void receive() {
    double last_sync = gaze_clock_ms();
    while (!stop_) {
      zmq_pollitem_t item{sub_, 0, ZMQ_POLLIN, 0};
      if (zmq_poll(&item, 1, 20) > 0 && (item.revents & ZMQ_POLLIN)) drain();
      const double now = gaze_clock_ms();
      if (clock_.wants_sync || now - last_sync >= p_.sync_every_ms) {
        last_sync = now;
        try {
          if (!sync_clock()) open_remote(200);  // a lost answer: start the REQ socket afresh
        } catch (const std::runtime_error& e) {  // never out of this thread: the session goes on
          std::lock_guard<std::mutex> lock(mutex_);
          problem_ = e.what();
        }
      }
    }
  }
  void drain() {
    for (;;) {
      zmq_msg_t topic, payload;
      zmq_msg_init(&topic);
      if (zmq_msg_recv(&topic, sub_, ZMQ_DONTWAIT) < 0) {
        zmq_msg_close(&topic);
        return;
      }
      const double arrival = gaze_clock_ms();
      std::string problem;
      bool has_payload = false;
      zmq_msg_init(&payload);
      if (zmq_msg_more(&topic)) {
        has_payload = zmq_msg_recv(&payload, sub_, 0) >= 0;
        while (zmq_msg_more(&payload)) {  // extra frames (raw buffers): read and ignored
          zmq_msg_t extra;
          zmq_msg_init(&extra);
          const int got = zmq_msg_recv(&extra, sub_, 0);
          const bool more = got >= 0 && zmq_msg_more(&extra);
          zmq_msg_close(&extra);
          if (!more) break;
        }
      }
      const std::string topic_text(static_cast<const char*>(zmq_msg_data(&topic)), zmq_msg_size(&topic));
      std::vector<pupil_gaze_message> data;
      if (!has_payload) problem = "a message without a payload frame";
      else
        problem = parse_pupil_gaze(topic_text, static_cast<const unsigned char*>(zmq_msg_data(&payload)),
                                   zmq_msg_size(&payload), data);
      zmq_msg_close(&topic);
      zmq_msg_close(&payload);
      std::vector<gaze_sample> samples;
      for (const pupil_gaze_message& m : data) {
        gaze_sample s;
        double x = m.norm_x, y = 1 - m.norm_y;  // Pupil's origin is bottom-left
        if (!calibration_.apply(x, y)) {
          problem = "the calibration maps the position to infinity";
          break;
        }
        s.x = x * width_, s.y = y * height_;
        s.tracker_s = m.timestamp, s.confidence = m.confidence, s.eye = m.eye;
        samples.push_back(s);
      }
      std::lock_guard<std::mutex> lock(mutex_);
      if (!problem.empty()) {
        ++malformed_, problem_ = problem;
        continue;
      }
      for (gaze_sample& s : samples) {
        s.t_ms = clock_.to_local(s.tracker_s, arrival);
        jumps_ = clock_.jumps;
        if (queue_.size() >= 100000) queue_.pop_front();  // nobody reads: keep the newest
        queue_.push_back(s);
      }
    }
  }
  void close() {
    if (sub_) zmq_close(sub_), sub_ = nullptr;
    if (req_) zmq_close(req_), req_ = nullptr;
    if (ctx_) zmq_ctx_term(ctx_), ctx_ = nullptr;
  }

  pupil_params p_;
  gaze_calibration calibration_;
  std::string host_;
  uint16_t remote_port_ = 0;
  void *ctx_ = nullptr, *req_ = nullptr, *sub_ = nullptr;
  tracker_clock clock_;  // the receiving thread's (and the constructor's before it starts)
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;  // guards what follows
  std::deque<gaze_sample> queue_;
  uint64_t malformed_ = 0, jumps_ = 0;
  std::string problem_;
};

}  // namespace

std::unique_ptr<gaze_source> pupil_gaze(const pupil_params& params, const gaze_calibration& calibration, int width,
                                        int height) {
  return std::make_unique<pupil_source>(params, calibration, width, height);
}

}  // namespace fov
