// Threshold tables (subject,condition,threshold) for fovstair analyze --thresholds, and the
// statistics computed from what they accept.
#include <cmath>

#include "analysis.h"
#include "fuzz_input.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "thresholds.csv");
  std::vector<threshold_value> values;
  fuzz::expect_clean(path, [&] { values = read_thresholds_csv(path); });
  if (values.empty()) return 0;
  for (const threshold_value& v : values) fuzz::require(std::isfinite(v.threshold) && v.threshold > 0, "thresholds are scales");
  try {
    const threshold_analysis a = analyze_thresholds(values);
    fuzz::require(std::isnan(a.F) || a.F >= 0, "F is not negative");
    fuzz::require(std::isnan(a.p) || (a.p >= 0 && a.p <= 1), "p lies in [0, 1]");
  } catch (const std::runtime_error&) {  // too few values for the statistics: a message, no file
  } catch (const std::exception& e) {
    fuzz::finding("an exception that is not a std::runtime_error escaped the analysis", e.what());
  }
  return 0;
}
