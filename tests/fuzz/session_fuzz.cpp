// fovstair session files (JSONL: header, trials, end), as analyze and run --resume read them.
#include "analysis.h"
#include "fuzz_input.h"
#include "session.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "S1-1.jsonl");
  fuzz::expect_clean(path, [&] {
    const session_data s = read_session(path);
    for (const threshold_value& v : thresholds_from_sessions({s}))
      fuzz::require(std::isfinite(v.threshold) && v.threshold > 0, "recorded thresholds are scales");
  });
  return 0;
}
