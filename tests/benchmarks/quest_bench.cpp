// QUEST+'s next-scale search (an expected-entropy pass over the whole likelihood table)
// at table sizes up to max_quest_plus_table, the largest a protocol may ask for; and
// QUEST's update for comparison. docs/fovstair.md quotes these.
#include <benchmark/benchmark.h>

#include "quest.h"

namespace {

// A trial (answer + next-scale search) with a table of about `range(0)` likelihoods:
// 21 scales, 21 thresholds, and as many slopes as fill the rest.
void QuestPlusTrial(benchmark::State& state) {
  fov::quest_plus_params p;
  const std::vector<double> grid = fov::procedure_grid(1, 3, 0.1);
  p.slopes.clear();
  for (int64_t i = 0; i < state.range(0) / (21 * 21); ++i) p.slopes.push_back(1 + 0.05 * double(i));
  fov::quest_plus q(p, grid, true);
  bool yes = true;
  for (auto _ : state) {
    q.answer(yes);
    yes = !yes;
    benchmark::DoNotOptimize(q.scale());
  }
  state.counters["likelihoods"] = double(grid.size() * q.parameter_combinations());
}
BENCHMARK(QuestPlusTrial)->Arg(21 * 21)->Arg(1 << 14)->Arg(1 << 16)->Arg(fov::max_quest_plus_table)->Unit(benchmark::kMillisecond);

void QuestTrial(benchmark::State& state) {
  fov::quest q(fov::quest_params{}, fov::procedure_grid(1, 3, 0.1), true);
  bool yes = true;
  for (auto _ : state) {
    q.answer(yes);
    yes = !yes;
    benchmark::DoNotOptimize(q.scale());
  }
}
BENCHMARK(QuestTrial)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
