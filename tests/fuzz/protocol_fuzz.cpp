// fovstair protocol JSON. A protocol that validates must run: every reachable scale named,
// and a session over it ends within the trials its rule allows.
#include "fuzz_input.h"
#include "protocol.h"
#include "session.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size), file = "protocol.json";
  fuzz::expect_clean(file, [&] {
    const stair_protocol p = parse_protocol(text, file);
    const std::vector<double> scales = reachable_scales(p);
    fuzz::require(!scales.empty() && scales.front() >= p.scale_min - 1e-9 && scales.back() <= p.scale_max + 1e-9,
                  "reachable scales within the range");
    for (double s : scales) fuzz::require(!pointset_path(p, s).empty(), "a file per scale");
    stair_session session(p, "S1");
    // Each series ends within max_trials staircase trials; catch trials come on top, so
    // allow them generously (a hang would trip libFuzzer's timeout first).
    const uint64_t limit = uint64_t(p.conditions.size()) * p.rule.max_trials * 64 + 64;
    for (uint64_t i = 0; !session.finished(); ++i) {
      fuzz::require(i < limit, "the session ends");
      const trial_plan t = session.next();
      session.record(t, (t.index * 7 + t.condition) % 3 != 0);
    }
  });
  return 0;
}
