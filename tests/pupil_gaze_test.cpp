// --gaze-pupil against a fake Pupil Remote and publisher on the loopback interface: the
// exchange, the coordinate mapping, malformed messages, a publisher that stops, a clock
// jump, an unreachable tracker and a server that is not Pupil Remote.
#include <zmq.h>
#include <msgpack.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "gaze_conditioning.h"
#include "pupil_gaze.h"

namespace fov {
namespace {

uint16_t bound_port(void* socket) {
  char endpoint[256];
  size_t size = sizeof(endpoint);
  zmq_getsockopt(socket, ZMQ_LAST_ENDPOINT, endpoint, &size);
  const std::string e(endpoint);
  return uint16_t(std::stoi(e.substr(e.rfind(':') + 1)));
}

// Pupil Remote (a REP socket answering SUB_PORT and t) and the IPC backbone's publisher.
// Pupil's clock is ours plus `clock_offset_s`.
class fake_pupil {
 public:
  explicit fake_pupil(std::string sub_port_answer = "") : sub_port_answer_(std::move(sub_port_answer)) {
    ctx_ = zmq_ctx_new();
    rep_ = zmq_socket(ctx_, ZMQ_REP);
    pub_ = zmq_socket(ctx_, ZMQ_PUB);
    const int zero = 0;
    zmq_setsockopt(rep_, ZMQ_LINGER, &zero, sizeof(zero));
    zmq_setsockopt(pub_, ZMQ_LINGER, &zero, sizeof(zero));
    EXPECT_EQ(zmq_bind(rep_, "tcp://127.0.0.1:*"), 0);
    EXPECT_EQ(zmq_bind(pub_, "tcp://127.0.0.1:*"), 0);
    remote_port = bound_port(rep_), pub_port = bound_port(pub_);
    server_ = std::thread([this] { serve(); });
  }
  ~fake_pupil() {
    stop_remote();
    zmq_close(pub_);
    zmq_ctx_term(ctx_);
  }
  std::string endpoint() const { return "tcp://127.0.0.1:" + std::to_string(remote_port); }
  double pupil_now() const { return gaze_clock_ms() / 1000 + clock_offset_s.load(); }
  // Pupil Remote stops answering (the publisher goes on).
  void stop_remote() {
    if (server_.joinable()) stop_ = true, server_.join(), zmq_close(rep_);
  }
  void publish(const std::string& topic, const std::string& payload, bool two_frames = true) {
    zmq_send(pub_, topic.data(), topic.size(), two_frames ? ZMQ_SNDMORE : 0);
    if (two_frames) zmq_send(pub_, payload.data(), payload.size(), 0);
  }
  // A gaze payload as Pupil Capture packs it (a map; norm_pos with origin bottom-left).
  static std::string gaze(double x, double y, double confidence, double timestamp, bool with_confidence = true) {
    msgpack_sbuffer buffer;
    msgpack_sbuffer_init(&buffer);
    msgpack_packer pk;
    msgpack_packer_init(&pk, &buffer, msgpack_sbuffer_write);
    auto key = [&](const char* k) {
      msgpack_pack_str(&pk, std::strlen(k));
      msgpack_pack_str_body(&pk, k, std::strlen(k));
    };
    msgpack_pack_map(&pk, with_confidence ? 4 : 3);
    key("topic");
    key("gaze.3d.01.");
    key("norm_pos");
    msgpack_pack_array(&pk, 2);
    msgpack_pack_double(&pk, x);
    msgpack_pack_double(&pk, y);
    if (with_confidence) key("confidence"), msgpack_pack_double(&pk, confidence);
    key("timestamp");
    msgpack_pack_double(&pk, timestamp);
    std::string out(buffer.data, buffer.size);
    msgpack_sbuffer_destroy(&buffer);
    return out;
  }

  // A surface tracker's message: gaze_on_surfaces with each datum's x, y (on the surface,
  // origin bottom-left), confidence and timestamp, topic "gaze.3d.0._on_surface".
  static std::string surface(const std::vector<std::array<double, 4>>& gaze) {
    msgpack_sbuffer buffer;
    msgpack_sbuffer_init(&buffer);
    msgpack_packer pk;
    msgpack_packer_init(&pk, &buffer, msgpack_sbuffer_write);
    auto key = [&](const char* k) {
      msgpack_pack_str(&pk, std::strlen(k));
      msgpack_pack_str_body(&pk, k, std::strlen(k));
    };
    msgpack_pack_map(&pk, 3);
    key("name");
    key("screen");
    key("timestamp");
    msgpack_pack_double(&pk, gaze.empty() ? 0.0 : gaze.back()[3]);
    key("gaze_on_surfaces");
    msgpack_pack_array(&pk, gaze.size());
    for (const auto& g : gaze) {
      msgpack_pack_map(&pk, 5);
      key("topic");
      key("gaze.3d.0._on_surface");
      key("norm_pos");
      msgpack_pack_array(&pk, 2);
      msgpack_pack_double(&pk, g[0]);
      msgpack_pack_double(&pk, g[1]);
      key("confidence");
      msgpack_pack_double(&pk, g[2]);
      key("on_surf");
      msgpack_pack_true(&pk);
      key("timestamp");
      msgpack_pack_double(&pk, g[3]);
    }
    std::string out(buffer.data, buffer.size);
    msgpack_sbuffer_destroy(&buffer);
    return out;
  }

  uint16_t remote_port = 0, pub_port = 0;
  std::atomic<double> clock_offset_s{5000};
  std::atomic<int> time_requests{0};

 private:
  void serve() {
    while (!stop_) {
      zmq_pollitem_t item{rep_, 0, ZMQ_POLLIN, 0};
      if (zmq_poll(&item, 1, 10) <= 0) continue;
      char buffer[256];
      const int n = zmq_recv(rep_, buffer, sizeof(buffer), 0);
      if (n < 0) continue;
      const std::string request(buffer, size_t(std::min(n, 255)));
      std::string answer = "Unknown command.";
      if (request == "SUB_PORT") answer = sub_port_answer_.empty() ? std::to_string(pub_port) : sub_port_answer_;
      if (request == "t") answer = std::to_string(pupil_now()), ++time_requests;
      zmq_send(rep_, answer.data(), answer.size(), 0);
    }
  }
  std::string sub_port_answer_;
  void *ctx_, *rep_, *pub_;
  std::thread server_;
  std::atomic<bool> stop_{false};
};

// Publishes `payload` every 10 ms until the source delivers a sample (ZeroMQ's subscriber
// joins a little after the connection), at most 5 s; returns what it delivered.
std::vector<gaze_sample> publish_until_read(fake_pupil& f, gaze_source& g, const std::string& topic,
                                            const std::function<std::string()>& payload) {
  std::vector<gaze_sample> got;
  const double until = gaze_clock_ms() + 5000;
  while (got.empty() && gaze_clock_ms() < until) {
    f.publish(topic, payload());
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    g.read(gaze_clock_ms(), got);
  }
  return got;
}

TEST(PupilGaze, ReceivesGazeMapsItToTheScreenAndToOurClock) {
  fake_pupil f;
  auto g = pupil_gaze({f.endpoint()}, {}, 400, 200);
  EXPECT_TRUE(g->live());
  EXPECT_EQ(g->name(), "pupil " + f.endpoint());
  const auto got = publish_until_read(f, *g, "gaze.3d.01.", [&] { return fake_pupil::gaze(0.25, 0.75, 0.9, f.pupil_now()); });
  ASSERT_FALSE(got.empty()) << "no gaze within 5 s";
  const gaze_sample& s = got.back();
  EXPECT_DOUBLE_EQ(s.x, 100);  // 0.25 of 400
  EXPECT_DOUBLE_EQ(s.y, 50);   // norm_pos y = 0.75 up from the bottom: 0.25 down from the top
  EXPECT_DOUBLE_EQ(s.confidence, 0.9);
  EXPECT_EQ(s.eye, gaze_eye::both);
  // Stamped by Pupil's clock, mapped to ours through the "t" exchange: taken within the last
  // 100 ms (loopback), never after now.
  const double now = gaze_clock_ms();
  EXPECT_LE(s.t_ms, now);
  EXPECT_GT(s.t_ms, now - 100);
  EXPECT_GE(f.time_requests.load(), 1);
  EXPECT_EQ(g->malformed, 0u);
  // Monocular topics name the eye (Pupil Core's eye 0 is the right eye).
  const auto right = publish_until_read(f, *g, "gaze.3d.0.", [&] { return fake_pupil::gaze(0.5, 0.5, 1, f.pupil_now()); });
  ASSERT_FALSE(right.empty());
  EXPECT_EQ(right.back().eye, gaze_eye::right);
}

// Subscribed to a surface (the screen, tracked by its markers): each gaze datum on it
// becomes a sample in the surface's coordinates.
TEST(PupilGaze, ReceivesGazeMappedOntoASurface) {
  fake_pupil f;
  pupil_params p{f.endpoint()};
  p.topic = "surfaces.screen";
  auto g = pupil_gaze(p, {}, 400, 200);
  const auto got = publish_until_read(f, *g, "surfaces.screen", [&] {
    return fake_pupil::surface({{0.25, 0.75, 0.9, f.pupil_now()}, {0.75, 0.25, 0.8, f.pupil_now()}});
  });
  ASSERT_GE(got.size(), 2u) << "no surface gaze within 5 s";
  EXPECT_DOUBLE_EQ(got[0].x, 100);
  EXPECT_DOUBLE_EQ(got[0].y, 50);
  EXPECT_DOUBLE_EQ(got[1].x, 300);
  EXPECT_DOUBLE_EQ(got[1].y, 150);
  EXPECT_EQ(got[1].eye, gaze_eye::right);
  EXPECT_EQ(g->malformed, 0u);
}

TEST(PupilGaze, CountsMalformedMessagesAndGoesOn) {
  fake_pupil f;
  auto g = pupil_gaze({f.endpoint()}, {}, 400, 200);
  ASSERT_FALSE(publish_until_read(f, *g, "gaze.3d.01.", [&] { return fake_pupil::gaze(0.5, 0.5, 1, f.pupil_now()); }).empty());
  f.publish("gaze.3d.01.", "not msgpack \xc1");
  f.publish("gaze.3d.01.", fake_pupil::gaze(0.5, 0.5, 1, f.pupil_now(), false));  // no confidence
  f.publish("gaze.3d.01.", "", false);                                              // no payload frame
  f.publish("gaze.3d.01.", "\x81\xa8norm_pos\xdd\xff\xff\xff\xff");                // declares 2^32 elements
  const auto got = publish_until_read(f, *g, "gaze.3d.01.", [&] { return fake_pupil::gaze(0.1, 0.1, 1, f.pupil_now()); });
  ASSERT_FALSE(got.empty());
  EXPECT_DOUBLE_EQ(got.back().x, 40);
  EXPECT_EQ(g->malformed, 4u);
  EXPECT_EQ(g->last_problem, "payload: a msgpack container declares more elements than the payload holds");
}

TEST(PupilGaze, APublisherThatStopsLeadsToTheSafeModeAndBack) {
  fake_pupil f;
  auto g = pupil_gaze({f.endpoint()}, {}, 400, 200);
  const display_geometry d{400, 200, 1.0};
  gaze_conditioning p;
  p.hold_ms = 100;
  gaze_conditioner c(p, d, g->live());
  const auto first = publish_until_read(f, *g, "gaze.3d.01.", [&] { return fake_pupil::gaze(0.25, 0.5, 1, f.pupil_now()); });
  ASSERT_FALSE(first.empty());
  gaze_estimate e = c.update(gaze_clock_ms(), first);
  EXPECT_EQ(e.state, gaze_state::tracking);
  EXPECT_DOUBLE_EQ(e.at.x, 100);
  // Pupil Remote stops answering and the publisher falls silent: held, then the centre.
  f.stop_remote();
  std::vector<gaze_sample> none;
  g->read(gaze_clock_ms(), none);
  e = c.update(gaze_clock_ms(), none);
  EXPECT_EQ(e.state, gaze_state::holding);
  EXPECT_DOUBLE_EQ(e.at.x, 100);
  std::this_thread::sleep_for(std::chrono::milliseconds(250));
  g->read(gaze_clock_ms(), none);
  e = c.update(gaze_clock_ms(), none);
  EXPECT_EQ(e.state, gaze_state::safe);
  EXPECT_DOUBLE_EQ(e.at.x, 200);
  EXPECT_EQ(c.dropouts, 1u);
  // It speaks again (Pupil Remote still silent: the source asks again, and goes on).
  const auto back = publish_until_read(f, *g, "gaze.3d.01.", [&] { return fake_pupil::gaze(0.75, 0.5, 1, f.pupil_now()); });
  ASSERT_FALSE(back.empty());
  e = c.update(gaze_clock_ms(), back);
  EXPECT_EQ(e.state, gaze_state::tracking);
  EXPECT_DOUBLE_EQ(e.at.x, 300);
  EXPECT_EQ(c.dropouts, 1u);
}

TEST(PupilGaze, AClockJumpIsCountedAndTheMappingFollows) {
  fake_pupil f;
  auto g = pupil_gaze({f.endpoint()}, {}, 400, 200);
  ASSERT_FALSE(publish_until_read(f, *g, "gaze.", [&] { return fake_pupil::gaze(0.5, 0.5, 1, f.pupil_now()); }).empty());
  const int requests_before = f.time_requests.load();
  f.clock_offset_s = f.clock_offset_s.load() + 1000;  // Pupil's clock is set forwards (e.g. "T" from another client)
  std::vector<gaze_sample> after;
  const double until = gaze_clock_ms() + 3000;
  while (gaze_clock_ms() < until && (after.size() < 20 || f.time_requests.load() == requests_before)) {
    f.publish("gaze.3d.01.", fake_pupil::gaze(0.5, 0.5, 1, f.pupil_now()));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    g->read(gaze_clock_ms(), after);
  }
  ASSERT_GE(after.size(), 20u);
  EXPECT_GE(g->clock_jumps, 1u);
  EXPECT_GT(f.time_requests.load(), requests_before);  // it asked for the time again
  // Every sample still maps to when it was taken: within 100 ms before its reading.
  const double now = gaze_clock_ms();
  for (const gaze_sample& s : after) {
    EXPECT_LE(s.t_ms, now);
    EXPECT_GT(s.t_ms, now - 3100);
  }
  EXPECT_GT(after.back().t_ms, now - 100);
}

TEST(PupilGaze, RefusesAnUnreachableTrackerAndAForeignServerInOneLine) {
  uint16_t closed_port = 0;
  {
    fake_pupil f;
    closed_port = f.remote_port;
  }
  const std::string endpoint = "tcp://127.0.0.1:" + std::to_string(closed_port);
  pupil_params p{endpoint};
  p.timeout_ms = 300;
  const double start = gaze_clock_ms();
  try {
    pupil_gaze(p, {}, 400, 200);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "--gaze-pupil " + endpoint +
                                         ": no answer from Pupil Remote within 300 ms (is Pupil Capture running, with "
                                         "Pupil Remote on this port?)");
  }
  EXPECT_LT(gaze_clock_ms() - start, 2000);
  fake_pupil foreign("hello");
  try {
    pupil_gaze({foreign.endpoint()}, {}, 400, 200);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "--gaze-pupil " + foreign.endpoint() + ": Pupil Remote answered 'hello' to SUB_PORT, not a port: is this Pupil Remote?");
  }
}

TEST(PupilGaze, ParsesEndpointsAndMessages) {
  std::string host;
  uint16_t port = 0;
  EXPECT_EQ(parse_pupil_endpoint("tcp://127.0.0.1:50020", host, port), "");
  EXPECT_EQ(host, "127.0.0.1");
  EXPECT_EQ(port, 50020);
  EXPECT_EQ(parse_pupil_endpoint("tcp://tracker-pc.local:50020", host, port), "");
  EXPECT_NE(parse_pupil_endpoint("127.0.0.1:50020", host, port), "");
  EXPECT_NE(parse_pupil_endpoint("udp://127.0.0.1:50020", host, port), "");
  EXPECT_EQ(parse_pupil_endpoint("tcp://h:70000", host, port), "port 70000 is not in 1..65535");
  std::vector<pupil_gaze_message> data;
  const std::string ok = fake_pupil::gaze(0.2, 0.3, 0.5, 12.5);
  auto parse = [&](const std::string& topic, const std::string& payload) {
    return parse_pupil_gaze(topic, reinterpret_cast<const unsigned char*>(payload.data()), payload.size(), data);
  };
  EXPECT_EQ(parse("gaze.2d.1.", ok), "");
  ASSERT_EQ(data.size(), 1u);
  EXPECT_EQ(data[0].eye, gaze_eye::left);
  EXPECT_DOUBLE_EQ(data[0].norm_y, 0.3);
  EXPECT_DOUBLE_EQ(data[0].timestamp, 12.5);
  EXPECT_EQ(parse("pupil.0.2d", ok), "topic 'pupil.0.2d' is not a gaze or surface topic");
  EXPECT_EQ(parse("g\t\n`", ok), "topic 'g\\t\\n`' is not a gaze or surface topic");  // a fuzz finding: one line, printable
  EXPECT_EQ(parse("gaze.3d.01.", ok + "x"), "payload: 1 bytes after the msgpack object");
  EXPECT_EQ(parse("gaze.3d.01.", ok.substr(0, ok.size() - 1)), "payload: the payload ends inside a msgpack object");
  EXPECT_EQ(parse("gaze.3d.01.", "\x92\x01\x02"), "payload: not a msgpack map");
  // The surface tracker: every gaze datum mapped onto the surface, each with its own topic.
  EXPECT_EQ(parse("surfaces.screen", fake_pupil::surface({{0.25, 0.75, 0.9, 20.0}, {0.5, 0.5, 0.8, 20.004}})), "");
  ASSERT_EQ(data.size(), 2u);
  EXPECT_DOUBLE_EQ(data[0].norm_x, 0.25);
  EXPECT_DOUBLE_EQ(data[1].timestamp, 20.004);
  EXPECT_EQ(data[0].eye, gaze_eye::right);  // "gaze.3d.0._on_surface"
  EXPECT_EQ(parse("surfaces.screen", fake_pupil::surface({})), "");  // no gaze on it this time
  EXPECT_TRUE(data.empty());
  EXPECT_EQ(parse("surfaces.screen", ok), "a surface message without gaze_on_surfaces");
}

}  // namespace
}  // namespace fov
