// fovbench's cached-reference sidecars (references/*.json), as a resumed or repeated sweep
// reads them back before it reuses a reference.
#include <cmath>

#include "bench.h"
#include "fuzz_input.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "reference.json");
  fuzz::expect_clean(path, [&] {
    const reference_meta m = read_reference_meta(path);
    fuzz::require(std::isfinite(m.ms) && m.ms >= 0, "a finite, non-negative time");
    fuzz::require(m.spp >= 1 && m.spp <= max_spp, "spp in range");
  });
  return 0;
}
