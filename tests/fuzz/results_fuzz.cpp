// fovbench's results.csv, as --resume, the plots and the report read it back, and as
// fovbench summary reads and answers it (older columns too).
#include <cmath>
#include <set>

#include "fuzz_input.h"
#include "report.h"
#include "sweep.h"

using namespace fov;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "results.csv");
  fuzz::expect_clean(path, [&] {
    const std::vector<result_row> rows = read_results(path);
    std::set<std::string> keys;
    for (const result_row& r : rows) {
      fuzz::require(r.cells.size() == result_columns().size(), "every row has every column");
      fuzz::require(keys.insert(r.key()).second, "one row per configuration");
      (void)r.number("psnr_db");
    }
    const std::vector<scheme_answer> answers = at_goal(scheme_answers_by_level(read_results(path, true)), goal_target_jod);
    for (const scheme_answer& a : answers) fuzz::require(a.reached == !std::isnan(a.speedup.estimate), "a price only where reached");
    (void)scheme_answers_markdown(answers);
  });
  return 0;
}
