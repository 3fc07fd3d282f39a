// A staircase experiment, as a protocol file describes it (schema: docs/fovstair.md).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "fov/reconstruct_params.h"
#include "fov/renderer.h"
#include "quest.h"

namespace fov {

// One condition: a name and the renderer settings it uses.
struct stair_condition {
  std::string name;
  reconstruct_params reconstruct;  // method, k, renka, RBF kernel and shape
  uint32_t spp = 0;                // 0: the protocol's
};

// The transformed up-down rule. The scale goes down (less foveation) after `down`
// consecutive detections and up after `up` consecutive misses; the thesis's method of
// limits with a staircase is up = down = 1, starting ascending. Steps are `initial_step`
// until the first reversal, `step` after; the first `discard_reversals` reversals give no
// threshold; the series ends after `thresholds` recorded reversals or `max_trials` trials.
// A series starts ascending, or descending when it starts at the top of the scale range.
struct stair_rule {
  uint32_t up = 1, down = 1;
  double initial_step = 0.2, step = 0.1;
  uint32_t discard_reversals = 1;
  uint32_t thresholds = 4;
  uint32_t max_trials = 80;
};

// How a series chooses its next scale: the transformed up-down rule (`rule`), QUEST or
// QUEST+ (`quest`, `quest_plus`; quest.h).
enum class stair_procedure : uint8_t { up_down, quest, quest_plus };
inline constexpr label_table<stair_procedure, 3> stair_procedure_labels = {
    {"up-down", stair_procedure::up_down}, {"quest", stair_procedure::quest}, {"quest-plus", stair_procedure::quest_plus}};

enum class stair_mode : uint8_t {
  yes_no,  // one interval: "anything unnatural?" (the thesis)
  two_afc  // two intervals, foveated and reference in random order: "which was foveated?"
};

// Fixation control: a trial whose gaze strays more than `radius_deg` from the fixation
// target while the stimulus is shown is marked in its record (`mark`), or shown again
// (`repeat`: the answer is not given to the procedure and a "repeat" record keeps it), at
// most `max_repeats` times in a row, after which it is recorded and marked.
enum class fixation_action : uint8_t { mark, repeat };
inline constexpr label_table<fixation_action, 2> fixation_action_labels = {{"mark", fixation_action::mark},
                                                                           {"repeat", fixation_action::repeat}};
struct fixation_control {
  double radius_deg = 2;  // 0: off
  fixation_action action = fixation_action::mark;
  uint32_t max_repeats = 3;
};

// Practice trials before a session's first trial (resumed if quit during them): `trials` showings at
// `scales` in turn (empty: scale max, the easiest), cycling through the conditions in the
// subject's order, never catch trials; with `feedback`, "Correct" / "Wrong" (2AFC) or
// "That one was foveated" (yes-no) after each. Recorded as "practice" records that no
// procedure or analysis uses.
struct practice_settings {
  uint32_t trials = 0;
  std::vector<double> scales;
  bool feedback = true;
};

struct stair_protocol {
  std::string name, description;
  std::string scene = "builtin";   // builtin, FILE or env:IMAGE
  std::string points_dir = "precomputed";  // relative to the working directory
  std::string display = "fove";    // a display spec (fov::parse_display); sets are named by pointset_file_name
  uint32_t spp = 4;
  bool taa = true;
  double hfov = 0;                 // 0: the scene's
  // How the stimuli are traced (render_params): the integrator, its bounces (path only) and
  // a lat-long image lighting the scene ("" for the scene's own environment; read when the
  // scene loads, as a scene file is).
  integrator method = integrator::direct;
  uint32_t bounces = 2;
  std::string env_light;
  std::vector<stair_condition> conditions;
  std::string order = "latin-square";  // latin-square (by subject number), fixed, random
  stair_mode mode = stair_mode::yes_no;
  double scale_min = 1.0, scale_max = 3.0, scale_start = 1.0;
  double scale_grid = 0.1;         // QUEST and QUEST+ show scale_min + i x scale_grid (and scale_max)
  stair_procedure procedure = stair_procedure::up_down;
  stair_rule rule;
  quest_params quest;
  quest_plus_params quest_plus;
  double catch_rate = 0.1;         // share of trials showing the reference instead
  std::vector<std::pair<double, double>> fixations{{0.5, 0.5}};  // normalised, in order
  fixation_control fixation;
  std::vector<std::string> instructions;  // the screen before the first trial (empty: the mode's, instruction_lines)
  std::string question;                   // empty: the mode's (question_text)
  practice_settings practice;
  double interval_ms = 1500;       // 2AFC: each interval's length
  uint32_t break_every = 0;        // a pause every N trials (0: only between conditions)
  uint64_t seed = 1;
};

// "FILE:LINE: what is wrong" for a malformed or invalid protocol.
struct protocol_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The deepest nesting of arrays and objects a protocol may have (the schema needs 3), and
// the largest protocol file.
constexpr int max_protocol_depth = 32;
constexpr uintmax_t max_protocol_bytes = 1u << 20;

// What a protocol's values may be, beyond their own rules (docs/fovstair.md): wide enough for
// any experiment a person can sit through, small enough that validate, simulate and run
// stay quick and small. Each error names its bound.
constexpr size_t max_protocol_conditions = 64;
constexpr double max_protocol_scale = 10;          // scales.max; scales.min is at least 0.5
constexpr uint32_t max_protocol_thresholds = 100;  // rule.thresholds and rule.discard_reversals
constexpr uint32_t max_protocol_series_trials = 1000;  // rule.max_trials
constexpr double max_protocol_catch_rate = 0.5;    // catch trials come on top of a series' trials
constexpr double max_protocol_interval_ms = 60000;
// The most staircase trials a session can plan (catch trials come on top).
constexpr uint64_t max_protocol_trials = uint64_t(max_protocol_conditions) * max_protocol_series_trials;

// Parses and validates; every error names the file and the line of the offending value.
stair_protocol load_protocol(const std::string& path);
// The protocol file's text, read as load_protocol reads it (a regular file of at most
// max_protocol_bytes; protocol_error naming the file otherwise): `run` stores it.
std::string read_protocol_text(const std::string& path);
stair_protocol parse_protocol(const std::string& text, const std::string& name_for_errors);

// The scales a series can visit: scale_min + i x step (and the initial steps), rounded to
// 0.01; for QUEST and QUEST+ the grid scale_min + i x scale_grid and scale_max.
std::vector<double> reachable_scales(const stair_protocol& p);

// The render parameters a condition's stimulus is shown with: its reconstruction and
// rays, the protocol's TAA and camera (hfov) and the renderer's defaults for the rest.
render_params stimulus_params(const stair_protocol& p, const stair_condition& c);

// What the subject reads: the protocol's instructions and question, or the mode's defaults.
std::vector<std::string> instruction_lines(const stair_protocol& p);
std::string question_text(const stair_protocol& p);
// The scale of practice trial i.
double practice_scale(const stair_protocol& p, uint32_t i);

// The step of the `fovgen sweep` that makes every set the protocol can show.
double sweep_step(const stair_protocol& p);

// The point-set file for a scale: <points_dir>/<fov::pointset_file_name> (a darts fovea).
std::string pointset_path(const stair_protocol& p, double scale);

}  // namespace fov
