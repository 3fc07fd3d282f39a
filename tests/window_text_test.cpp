// Text that fits the window: the overlay and fovstair's screens wrap and shrink their lines
// to the window's width (a 640-pixel window cut them off).
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "window.h"

namespace fov {
namespace {

TEST(WindowText, WrapsAtSpacesToFitTheWidth) {
  const std::string line =
      "12.3 fps  trace 10.1  reconstruct 5.2  TAA 1.1  display 2.0  gaze-to-screen 21.0 ms";
  const fitted_text wide = fit_text({line}, 2000, 0.5, 1);
  ASSERT_EQ(wide.lines.size(), 1u);  // room enough: unchanged, double spaces too
  EXPECT_EQ(wide.lines[0], line);
  EXPECT_EQ(wide.scale, 0.5);
  const fitted_text narrow = fit_text({line, "", "H: help"}, 300, 0.5, 1);
  EXPECT_EQ(narrow.scale, 0.5);  // every word fits: wrapped, not shrunk
  EXPECT_GT(narrow.lines.size(), 3u);
  EXPECT_LE(narrow.width, 300);
  std::string joined;
  for (const std::string& l : narrow.lines) {
    EXPECT_LE(cv::getTextSize(l, cv::FONT_HERSHEY_SIMPLEX, narrow.scale, 1, nullptr).width, 300) << l;
    if (!l.empty()) joined += (joined.empty() ? "" : " ") + l;
  }
  EXPECT_EQ(joined, "12.3 fps trace 10.1 reconstruct 5.2 TAA 1.1 display 2.0 gaze-to-screen 21.0 ms H: help");
  EXPECT_EQ(narrow.lines.back(), "H: help");  // the empty line kept as a gap
}

TEST(WindowText, ShrinksForAWordWiderThanTheWindow) {
  const fitted_text t = fit_text({"gaze pupil tcp://192.168.100.200:50020"}, 200, 0.5, 1);
  EXPECT_LT(t.scale, 0.5);
  for (const std::string& l : t.lines)
    EXPECT_LE(cv::getTextSize(l, cv::FONT_HERSHEY_SIMPLEX, t.scale, 1, nullptr).width, 200) << l;
  // Below 0.3 text stops being legible: there it stays, and the box is cut at the edge.
  const fitted_text floor = fit_text({"tcp://192.168.100.200:50020"}, 40, 0.5, 1);
  EXPECT_GE(floor.scale, 0.3);
  EXPECT_LT(floor.scale, 0.3 / 0.9);
}

TEST(WindowText, MessageScreensKeepTheirTextInside640Pixels) {
  // fovstair's pause text at the 640-pixel width the issue found cut off: no white pixel in
  // the right margin (an eighth of the width), as there was when the text ran past the edge.
  const cv::Mat m = message_screen(640, 480, {"Paused.", "Any key resumes this trial; Q quits (the session can be resumed)."});
  const cv::Mat margin = m(cv::Rect(640 - 640 / 8 + 4, 0, 640 / 8 - 4, 480));
  cv::Mat grey;
  cv::cvtColor(margin, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::countNonZero(grey > 128), 0);
  cv::Mat all;
  cv::cvtColor(m, all, cv::COLOR_BGR2GRAY);
  EXPECT_GT(cv::countNonZero(all > 128), 500);  // the text is there
}

}  // namespace
}  // namespace fov
