// Gaze sources: CSV replay timing, UDP datagrams on loopback, malformed and out-of-range input.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include <gtest/gtest.h>

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

TEST(GazeUdp, ParsesDatagrams) {
  double x = 0, y = 0;
  EXPECT_TRUE(parse_gaze_datagram("0.25 0.75", x, y));
  EXPECT_EQ(x, 0.25);
  EXPECT_EQ(y, 0.75);
  EXPECT_TRUE(parse_gaze_datagram("  0.5\t0.5\n", x, y));
  EXPECT_FALSE(parse_gaze_datagram("0.5", x, y));
  EXPECT_FALSE(parse_gaze_datagram("0.5 0.5 0.5", x, y));
  EXPECT_FALSE(parse_gaze_datagram("x y", x, y));
  EXPECT_FALSE(parse_gaze_datagram("nan 0.5", x, y));
}

TEST(GazeUdp, ReadsLoopbackDatagramsClampsAndWarnsWhenSilent) {
  std::unique_ptr<gaze_source> g;
  uint16_t port = 0;
  for (uint16_t p = 47000; p < 47100 && !g; ++p) {  // a free port
    try {
      g = udp_gaze(p, 400, 200);
      port = p;
    } catch (const std::runtime_error&) {
    }
  }
  ASSERT_TRUE(g) << "no free UDP port in 47000..47099";
  const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  auto send = [&](const std::string& text) {
    ::sendto(s, text.data(), text.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
  };
  gaze_point p;
  p = g->poll(0);
  EXPECT_EQ(p.x, 200);  // nothing yet: the centre
  EXPECT_TRUE(g->silent(0));
  send("0.25 0.5");
  send("garbage");
  send("0.5 1.5");  // off screen: clamped
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  p = g->poll(1000);
  EXPECT_EQ(p.x, 200);  // the newest datagram wins
  EXPECT_EQ(p.y, 200);
  EXPECT_EQ(g->malformed, 1u);
  EXPECT_EQ(g->clamped, 1u);
  EXPECT_FALSE(g->silent(1400));
  EXPECT_TRUE(g->silent(1600));  // 500 ms without a datagram
  p = g->poll(1600);
  EXPECT_EQ(p.y, 200);  // keeps the last gaze
  ::close(s);
}

}  // namespace
}  // namespace fov
