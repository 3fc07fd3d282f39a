// fovbench's data handling: the Pareto front, results.csv round trips, torn lines.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "sweep.h"

namespace fov {
namespace {

TEST(Pareto, KeepsOnlyUndominatedPointsSortedByTime) {
  // (time, error): b dominates d; e ties a in time with more error; f is NaN.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> x = {1, 2, 4, 3, 1, 5, nan, 8};
  const std::vector<double> y = {9, 5, 1, 6, 10, 1, 0, 0.5};
  //                              a  b  c  d  e   f  g    h
  const std::vector<size_t> front = pareto_front(x, y);
  EXPECT_EQ(front, (std::vector<size_t>{0, 1, 2, 7}));  // a, b, c, h (f ties c's error but is slower)
  EXPECT_TRUE(pareto_front({}, {}).empty());
}

result_row sample_row(const std::string& method, const std::string& spp) {
  result_row r;
  for (const std::string& c : result_columns()) r.cells[c] = "1.5";
  r.cells["scene"] = "env:/tmp/a, \"quoted\" name.exr";  // commas and quotes survive
  r.cells["method"] = method;
  r.cells["spp"] = spp;
  r.cells["psnr"] = "inf";
  r.cells["flicker"] = "";
  r.cells["error_profile"] = "0.1;0.2;0.05";
  return r;
}

TEST(ResultsCsv, RoundTripsEveryCellAndKey) {
  const std::string path = ::testing::TempDir() + "/results-roundtrip.csv";
  std::filesystem::remove(path);
  {
    results_writer w(path);
    w.append(sample_row("nn", "1"));
    w.append(sample_row("rbf", "32"));
  }
  const std::vector<result_row> rows = read_results(path);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].cells, sample_row("nn", "1").cells);
  EXPECT_EQ(rows[1].key(), sample_row("rbf", "32").key());
  EXPECT_NE(rows[0].key(), rows[1].key());
  EXPECT_TRUE(std::isinf(rows[0].number("psnr")));
  EXPECT_TRUE(std::isnan(rows[0].number("flicker")));
  EXPECT_DOUBLE_EQ(rows[0].number("frame_ms"), 1.5);
}

TEST(ResultsCsv, ATornLastLineIsIgnoredAndCutOnTheNextWrite) {
  const std::string path = ::testing::TempDir() + "/results-torn.csv";
  std::filesystem::remove(path);
  {
    results_writer w(path);
    w.append(sample_row("nn", "1"));
  }
  std::ofstream(path, std::ios::app) << "builtin,centre,48,40,1.00,shep";  // interrupted mid-row
  EXPECT_EQ(read_results(path).size(), 1u);
  {
    results_writer w(path);  // resuming: the torn bytes go, the new row follows the last whole one
    w.append(sample_row("shepard", "4"));
  }
  const std::vector<result_row> rows = read_results(path);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].text("method"), "shepard");
}

TEST(ResultsCsv, AForeignFileIsRefusedWithItsLine) {
  const std::string path = ::testing::TempDir() + "/results-foreign.csv";
  std::ofstream(path) << "a,b,c\n1,2,3\n";
  try {
    read_results(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ":1: not a results.csv of this fovbench (columns differ); use another -o");
  }
}

}  // namespace
}  // namespace fov
