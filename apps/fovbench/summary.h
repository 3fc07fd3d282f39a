// fovbench summary: one answer per display (issue 24, item 5). Reads the results.csv of many
// runs (displays, scenes, fovea layouts, steady states), asks each scheme the goal's question
// (scheme_answers_by_level, at_goal: its equal-quality speedup at the cheapest full frame
// reaching the target JOD) and keeps, per scene, steady state, display and scheme, the best
// answer of any run.
#pragma once

#include <string>
#include <vector>

#include "report.h"

namespace fov {

struct summary_options {
  // results.csv files, or directories searched (recursively, not through links) for them.
  std::vector<std::string> inputs;
  std::string out;  // summary.md, summary.csv, speedup-vs-ppd and jod-vs-ppd (.png, .svg)
  double target_jod = goal_target_jod;
};

struct summary_result {
  std::vector<std::string> files;      // the results.csv read, in order
  std::vector<scheme_answer> answers;  // the best per scene, steady state, display and scheme
  std::vector<std::string> warnings;   // figures that could not be drawn
};

// The largest number of results.csv files one summary reads.
constexpr size_t max_summary_files = 4096;

// Refuses (usage_error naming the flag or input) no inputs, an input that does not exist or
// holds no results.csv, more than max_summary_files, a missing -o or one that already holds a
// summary.md, a target outside 0..10; std::runtime_error "FILE: reason" for a results.csv
// that read_results refuses or two runs whose full frame at the same spp scores differently
// on the same scene and display (different references: not one study). Writes nothing
// before every input is read.
summary_result write_summary(const summary_options& s, int argc, char** argv);

}  // namespace fov
