// Gaze sources: CSV replay timing, UDP datagrams on loopback, malformed and out-of-range input.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "gaze_log.h"
#include "gaze_source.h"

namespace fov {
namespace {

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(GazeTrace, ReplaysByTimeInPixelsOrNormalised) {
  auto g = trace_gaze(write_temp("px.csv", "t_ms,x,y\n0,10,20\n100,30,40\n250,50,60\n"), 200, 100);
  gaze_point p;
  p = g->poll(0);
  EXPECT_EQ(p.x, 10);
  p = g->poll(99.9);
  EXPECT_EQ(p.x, 10);  // the last sample at or before now: no interpolation
  p = g->poll(100);
  EXPECT_EQ(p.y, 40);
  p = g->poll(1000);
  EXPECT_EQ(p.x, 50);  // after the end the gaze stays
  auto n = trace_gaze(write_temp("norm.csv", "t_ms,x_norm,y_norm\n0,0.25,0.5\n"), 200, 100);
  p = n->poll(5);
  EXPECT_EQ(p.x, 50);
  EXPECT_EQ(p.y, 50);
}

// Other tools' exports: Pupil Player's gaze_positions.csv (seconds, norm_pos from the
// bottom-left, a confidence, extra columns) and a generic tab-separated export in
// microseconds and pixels with a lost sample.
TEST(GazeExport, PupilPlayerAndMappedColumns) {
  trace_columns pupil;
  ASSERT_EQ(parse_trace_columns("pupil", pupil), "");
  auto g = table_gaze(write_temp("gaze_positions.csv",
                                 "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y,base_data\n"
                                 "1234.500,0,0.9,0.25,0.25,1234.49-0 1234.50-1\n"
                                 "1234.600,1,0.4,0.5,0.75,1234.59-0\n"
                                 "1234.700,2,0.95,,,\n"),
                      pupil, 200, 100);
  std::vector<gaze_sample> out;
  g->read(1000, out);  // the first row at once
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].x, 50);
  EXPECT_DOUBLE_EQ(out[0].y, 75);  // 0.25 from the bottom
  EXPECT_DOUBLE_EQ(out[0].confidence, 0.9);
  g->read(1100, out);  // 100 ms later: the second row
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[1].y, 25);
  EXPECT_DOUBLE_EQ(out[1].confidence, 0.4);
  EXPECT_EQ(g->malformed, 1u);  // the row without a position
  trace_columns tobii;
  ASSERT_EQ(parse_trace_columns("Recording timestamp,Gaze point X,Gaze point Y;time=us", tobii), "");
  auto t = table_gaze(write_temp("tobii.tsv", "Recording timestamp\tGaze point X\tGaze point Y\n"
                                              "5000000\t10\t20\n5100000\t\t\n5200000\t30\t40\n"),
                      tobii, 200, 100);
  gaze_point p = t->poll(0);
  EXPECT_EQ(p.x, 10);
  p = t->poll(200);
  EXPECT_EQ(p.y, 40);
  EXPECT_EQ(t->malformed, 1u);
  try {
    table_gaze(write_temp("other.csv", "time,px,py\n0,1,2\n"), tobii, 200, 100);
    ADD_FAILURE() << "a missing column was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no column 'Recording timestamp' (the header has: time, px, py)"), std::string::npos)
        << e.what();
  }
  trace_columns bad;
  EXPECT_NE(parse_trace_columns("t,x", bad), "");
  EXPECT_NE(parse_trace_columns("t,x,y;time=min", bad), "");
  EXPECT_THROW(table_gaze(write_temp("back.csv", "t,x,y\n10,1,1\n5,1,1\n"), [] {
                 trace_columns c;
                 parse_trace_columns("t,x,y", c);
                 return c;
               }(), 200, 100),
               std::runtime_error);
}

// A gaze log reads back exactly what each frame used (the replay's promise), and a row out
// of order or a landing without its onset is refused with its line.
TEST(GazeLog, RoundTripsEveryFrameExactly) {
  gaze_log_row a;
  a.frame = 0, a.local_ms = 16.666666666666668, a.sample_local_ms = 10.5, a.shown_ms = 20;
  a.estimate.at = {0.1 + 0.2, 1.0 / 3};
  a.estimate.has_sample = true;
  gaze_log_row b = a;
  b.frame = 1, b.estimate.landed = true, b.estimate.saccade_onset = {2.0 / 7, 5}, b.estimate.state = gaze_state::saccade;
  b.sample_local_ms = std::numeric_limits<double>::quiet_NaN();
  const std::string path = write_temp("log.csv", gaze_log_header() + gaze_log_line(a) + gaze_log_line(b));
  const std::vector<gaze_log_row> r = read_gaze_log(path);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].estimate.at.x, a.estimate.at.x);  // bit for bit
  EXPECT_EQ(r[0].estimate.at.y, a.estimate.at.y);
  EXPECT_EQ(r[0].local_ms, a.local_ms);
  EXPECT_TRUE(r[0].estimate.has_sample);
  EXPECT_TRUE(r[1].estimate.landed);
  EXPECT_EQ(r[1].estimate.saccade_onset.x, 2.0 / 7);
  EXPECT_EQ(r[1].estimate.state, gaze_state::saccade);
  EXPECT_FALSE(r[1].estimate.has_sample);
  try {
    read_gaze_log(write_temp("skip.csv", gaze_log_header() + gaze_log_line(b)));
    ADD_FAILURE() << "a log starting at frame 1 was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("skip.csv:2: frame 1, expected 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_gaze_log(write_temp("trace.csv", "t_ms,x,y\n0,1,2\n")), std::runtime_error);
}

TEST(GazeTrace, ClampsAndCountsOffScreenSamplesOnce) {
  auto g = trace_gaze(write_temp("off.csv", "t_ms,x,y\n0,-5,20\n10,300,20\n20,5,5\n"), 200, 100);
  gaze_point p;
  p = g->poll(0);
  EXPECT_EQ(p.x, 0);
  p = g->poll(1);  // the same sample again: not counted twice
  p = g->poll(10);
  EXPECT_EQ(p.x, 200);
  p = g->poll(20);
  EXPECT_EQ(g->clamped, 2u);
}

TEST(GazeTrace, MalformedFilesNameTheLine) {
  auto message = [](const std::string& text) {
    try {
      trace_gaze(write_temp("bad.csv", text), 100, 100);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string p = ::testing::TempDir() + "/bad.csv";
  EXPECT_EQ(message("time,x,y\n0,1,1\n"), p + ":1: the header must be t_ms,x,y (pixels) or t_ms,x_norm,y_norm (0..1)");
  EXPECT_EQ(message("t_ms,x,y\n0,1,1\n5,abc,1\n"), p + ":3: expected 3 numbers t_ms,x,y");
  EXPECT_EQ(message("t_ms,x,y\n0,1,1,4\n"), p + ":2: more than 3 cells");
  EXPECT_EQ(message("t_ms,x,y\n10,1,1\n5,1,1\n"), p + ":3: time goes backwards (5 after 10)");
  EXPECT_EQ(message("t_ms,x,y\n"), p + ": no gaze samples");
  EXPECT_EQ(message("t_ms,x,y\n0,nan,1\n"), p + ":2: expected 3 numbers t_ms,x,y");
}

TEST(GazeUdp, ParsesBothDatagramVersions) {
  gaze_datagram d;
  EXPECT_EQ(parse_gaze_datagram("0.25 0.75", d), "");
  EXPECT_EQ(d.x, 0.25);
  EXPECT_EQ(d.y, 0.75);
  EXPECT_TRUE(std::isnan(d.t_s));
  EXPECT_EQ(d.confidence, 1);
  EXPECT_EQ(parse_gaze_datagram("  0.5\t0.5\n", d), "");
  EXPECT_EQ(parse_gaze_datagram("0.5,0.5", d), "");  // commas read as separators
  EXPECT_EQ(parse_gaze_datagram("v2 1234.5 0.9 l 0.1 0.2", d), "");
  EXPECT_EQ(d.t_s, 1234.5);
  EXPECT_EQ(d.confidence, 0.9);
  EXPECT_EQ(d.eye, gaze_eye::left);
  EXPECT_EQ(d.y, 0.2);
  EXPECT_EQ(parse_gaze_datagram("v2,7,1,R,0.5,0.5", d), "");
  EXPECT_EQ(d.eye, gaze_eye::right);
  EXPECT_EQ(parse_gaze_datagram("0.5", d), "expected 'X Y' (version 1) or 'v2 T C EYE X Y', got 1 fields");
  EXPECT_EQ(parse_gaze_datagram("0.5 0.5 0.5", d), "expected 'X Y' (version 1) or 'v2 T C EYE X Y', got 3 fields");
  EXPECT_EQ(parse_gaze_datagram("x y", d), "position 'x y' is not two numbers");
  EXPECT_EQ(parse_gaze_datagram("nan 0.5", d), "position 'nan 0.5' is not two numbers");
  EXPECT_EQ(parse_gaze_datagram("", d), "an empty datagram");
  EXPECT_EQ(parse_gaze_datagram("v2 1 1.5 b 0.5 0.5", d), "version 2: confidence '1.5' is not a number in 0..1");
  EXPECT_EQ(parse_gaze_datagram("v2 1 1 x 0.5 0.5", d), "version 2: eye 'x' is not l, r or b");
  EXPECT_EQ(parse_gaze_datagram("v2 inf 1 b 0.5 0.5", d), "version 2: time 'inf' is not a number");
  EXPECT_EQ(parse_gaze_datagram("v2 1 1 b 0.5", d), "version 2 needs 'v2 T C EYE X Y' (6 fields), got 5");
}

// A free loopback UDP port with a source on it.
std::unique_ptr<gaze_source> udp_on_free_port(uint16_t& port, const gaze_calibration& c = {}) {
  for (uint16_t p = 47000; p < 47100; ++p) {
    try {
      auto g = udp_gaze(p, 400, 200, c);
      port = p;
      return g;
    } catch (const std::runtime_error&) {
    }
  }
  return nullptr;
}

struct udp_sender {
  explicit udp_sender(uint16_t port) : fd(::socket(AF_INET, SOCK_DGRAM, 0)) {
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  }
  ~udp_sender() { ::close(fd); }
  void send(const std::string& text) {
    ::sendto(fd, text.data(), text.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
  }
  int fd;
  sockaddr_in to{};
};

TEST(GazeUdp, ReadsLoopbackDatagramsCountsMalformedAndClamps) {
  uint16_t port = 0;
  auto g = udp_on_free_port(port);
  ASSERT_TRUE(g) << "no free UDP port in 47000..47099";
  EXPECT_TRUE(g->live());
  udp_sender out(port);
  std::vector<gaze_sample> got;
  g->read(0, got);
  EXPECT_TRUE(got.empty());
  out.send("0.25 0.5");
  out.send("garbage");
  out.send("0.5 1.5");  // off screen: clamped
  out.send("v2 100.0 0.8 r 0.75 0.25");
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  g->read(1000, got);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].x, 100);
  EXPECT_EQ(got[0].y, 100);
  EXPECT_EQ(got[1].y, 200);  // clamped
  EXPECT_EQ(got[2].x, 300);
  EXPECT_EQ(got[2].y, 50);
  EXPECT_EQ(got[2].confidence, 0.8);
  EXPECT_EQ(got[2].eye, gaze_eye::right);
  EXPECT_EQ(got[2].tracker_s, 100.0);
  EXPECT_EQ(got[2].t_ms, 1000);  // the first stamped sample anchors the tracker's clock
  EXPECT_EQ(g->malformed, 1u);
  EXPECT_EQ(g->last_problem, "expected 'X Y' (version 1) or 'v2 T C EYE X Y', got 1 fields");
  EXPECT_EQ(g->clamped, 1u);
  EXPECT_EQ(g->samples, 3u);
}

TEST(GazeUdp, CalibrationMapsBeforeScaling) {
  const std::string path = write_temp("cal.json", R"({"offset": [0.1, -0.1], "scale": [0.5, 2]})");
  uint16_t port = 0;
  auto g = udp_on_free_port(port, read_gaze_calibration(path));
  ASSERT_TRUE(g);
  udp_sender out(port);
  out.send("0.4 0.3");
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::vector<gaze_sample> got;
  g->read(0, got);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_NEAR(got[0].x, (0.5 * 0.4 + 0.1) * 400, 1e-9);
  EXPECT_NEAR(got[0].y, (2 * 0.3 - 0.1) * 200, 1e-9);
}

TEST(TrackerClock, MapsBySyncFollowsTheSmallestDelayAndCountsJumps) {
  tracker_clock c(1000);
  // Without a sync: the first sample anchors; a sample that arrives sooner lowers the delay.
  EXPECT_EQ(c.to_local(10.0, 5000), 5000);
  EXPECT_EQ(c.to_local(10.1, 5120), 5100);  // 20 ms in transit
  EXPECT_EQ(c.to_local(10.2, 5195), 5195);  // sooner: the new smallest delay
  EXPECT_EQ(c.to_local(10.3, 5300), 5295);
  EXPECT_EQ(c.jumps, 0u);
  // A sync: the answer lies half way between send and receive.
  c.sync(20.0, 9000, 9010);
  EXPECT_DOUBLE_EQ(c.offset_ms(), 9005 - 20000);
  EXPECT_DOUBLE_EQ(c.to_local(20.5, 9520), 9505);
  // The tracker's clock jumps forwards by 1000 s: the sample cannot come from the future.
  EXPECT_DOUBLE_EQ(c.to_local(1020.6, 9610), 9610);
  EXPECT_EQ(c.jumps, 1u);
  EXPECT_TRUE(c.wants_sync);
  EXPECT_DOUBLE_EQ(c.to_local(1020.7, 9715), 9710);  // re-anchored on the jump
  // ... and backwards: 2 s old on arrival is more than max_age.
  EXPECT_DOUBLE_EQ(c.to_local(1018.0, 9800), 9800);
  EXPECT_EQ(c.jumps, 2u);
}

TEST(GazeCalibration, ReadsTheThreeFormsAndRefusesBadFiles) {
  gaze_calibration h = read_gaze_calibration(write_temp("h.json", R"({"homography": [2, 0, 0, 0, 2, 0, 0, 0, 2]})"));
  double x = 0.3, y = 0.7;
  EXPECT_TRUE(h.apply(x, y));
  EXPECT_DOUBLE_EQ(x, 0.3);
  EXPECT_DOUBLE_EQ(y, 0.7);
  // A validation grid whose tracker positions are the targets shrunk towards the centre and
  // shifted: the fitted mapping undoes it and reports its residual.
  std::string grid = R"({"grid": [)";
  for (int i = 0; i < 9; ++i) {
    const double sx = 0.1 + 0.4 * (i % 3), sy = 0.1 + 0.4 * (i / 3);
    grid += fmt::format("{}[{}, {}, {}, {}]", i ? ", " : "", 0.5 + 0.8 * (sx - 0.5) + 0.02, 0.5 + 0.9 * (sy - 0.5) - 0.01, sx, sy);
  }
  grid += "]}";
  gaze_calibration g = read_gaze_calibration(write_temp("grid.json", grid));
  EXPECT_EQ(g.fit_points, 9u);
  EXPECT_LT(g.fit_rms, 1e-6);  // OpenCV's least squares, in screen widths
  x = 0.5 + 0.8 * (0.25 - 0.5) + 0.02, y = 0.5 + 0.9 * (0.8 - 0.5) - 0.01;
  EXPECT_TRUE(g.apply(x, y));
  EXPECT_NEAR(x, 0.25, 1e-6);
  EXPECT_NEAR(y, 0.8, 1e-6);
  auto message = [](const std::string& text) {
    const std::string path = write_temp("badcal.json", text);
    try {
      read_gaze_calibration(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what()).substr(path.size());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(message("{"), ": not JSON");
  EXPECT_EQ(message("[]"), ": expected an object with \"offset\" and \"scale\", \"homography\" or \"grid\"");
  EXPECT_EQ(message(R"({"homography": [1, 2]})"), ": \"homography\" must be 9 numbers");
  EXPECT_EQ(message(R"({"scale": [0, 1]})"), ": a \"scale\" of 0 maps every gaze to one line");
  EXPECT_EQ(message(R"({"homography": [1,0,0, 0,1,0, 0,0,1], "grid": []})"),
            ": give one of \"offset\"/\"scale\", \"homography\" or \"grid\"");
  EXPECT_EQ(message(R"({"grid": [[0,0,0,0],[0.5,0.5,0.5,0.5],[1,1,1,1],[0.25,0.25,0.25,0.25]]})"),
            ": the grid's targets do not fix a mapping (collinear or repeated points)");
  EXPECT_EQ(message(R"({"homography": [1,0,0, 0,1,0, -2,0,1]})"), ": the mapping sends the screen's centre to infinity");
  EXPECT_EQ(message(R"({"offset": [0, 0], "shear": 1})"), ": unknown key \"shear\"");
}

}  // namespace
}  // namespace fov
