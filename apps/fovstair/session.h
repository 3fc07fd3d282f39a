// A subject's session: the order of conditions, each trial's plan, and the data file.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../common/line_log.h"
#include "protocol.h"
#include "staircase.h"

namespace fov {

// The number in a subject id ("S07" -> 7): the row of the Latin square. Ids without
// digits use a hash of the id.
uint64_t subject_number(const std::string& subject);

// Condition indices in the order this subject runs them: a balanced Latin square
// (Williams design; 2n rows for odd n) row chosen by the subject number, the protocol's
// order, or a shuffle seeded by seed and subject.
std::vector<uint32_t> condition_order(const stair_protocol& p, const std::string& subject);

struct trial_plan {
  uint64_t index = 0;          // trial number in the session, from 0
  uint32_t condition = 0;      // index into the protocol's conditions
  uint32_t series_trial = 0;   // staircase trials of this condition so far
  double scale = 1;
  bool is_catch = false;       // shows the reference: the staircase ignores the answer
  double fixation_x = 0.5, fixation_y = 0.5;  // normalised
  uint32_t foveated_interval = 0;  // 2AFC: which interval (0 or 1) shows the foveated frame
  bool break_before = false;   // a pause first (new condition or every break_every trials)
};

// The experiment's state: deterministic given protocol, subject and the answers so far.
class stair_session {
 public:
  stair_session(const stair_protocol& p, const std::string& subject);
  bool finished() const { return current_ >= order_.size(); }
  trial_plan next() const;  // the trial to run now; only when !finished()
  // Records the answer to next(); returns what it did to the staircase (nothing on catch trials).
  staircase::step record(const trial_plan& t, bool detected);

  const std::vector<uint32_t>& order() const { return order_; }
  const stair_series& series(uint32_t condition) const { return stairs_[condition]; }
  uint64_t trials() const { return trials_; }

 private:
  const stair_protocol& p_;
  std::string subject_;
  std::vector<uint32_t> order_;
  std::vector<stair_series> stairs_;
  size_t current_ = 0;
  uint64_t trials_ = 0;
  uint64_t series_began_at_ = 0;  // the trial index the current condition's series began at
  uint64_t seed_ = 0;
};

// The session file, data/<subject>-<session>.jsonl: a header line, one line per trial,
// an end line. Each line is written and fsync'ed before the call returns.
class session_file {
 public:
  // Creates the file; fails (std::runtime_error naming it) if it exists.
  static session_file create(const std::string& path, const nlohmann::json& header);
  // Opens an existing session to continue it: returns its header and trials. A torn
  // last line (a crash while writing) is cut off; a finished session is refused.
  // Refuses (before touching the file) a session of another subject or one that ended.
  static session_file resume(const std::string& path, const std::string& subject, nlohmann::json& header,
                             std::vector<nlohmann::json>& trials);
  void append(const nlohmann::json& record);

 private:
  explicit session_file(line_log log) : log_(std::move(log)) {}
  line_log log_;
};

// The trial record a session file holds for `t`, answered `detected` with the rule's `step`
// (run_session adds the response, timing and gaze fields).
nlohmann::json trial_record(const stair_protocol& p, const trial_plan& t, bool detected, const staircase::step& step);

// The largest session file: far above what any protocol's trials write (a record is a few
// hundred bytes and a protocol plans at most max_protocol_trials).
constexpr uintmax_t max_session_bytes = uintmax_t(1) << 30;

// Reads every line of a session file (for analysis and --resume): header, trials, and
// whether it ended. Checks every record against the protocol stored in the header: each
// trial must be the one that protocol plans next for the subject, carry the fields
// trial_record writes and record what the rule did with its answer; a duplicated,
// missing or spliced trial, a trial after the plan's last, or a record after the end
// record is refused. A torn last line (a crash while writing) is ignored, but a torn
// header is refused. Throws std::runtime_error "FILE:LINE: reason".
struct session_data {
  nlohmann::json header;
  std::vector<nlohmann::json> trials;
  std::vector<nlohmann::json> repeats;  // trials shown again after broken fixation (fixation_control "repeat")
  std::vector<nlohmann::json> practice;  // practice trials before the first trial
  bool ended = false;
};
session_data read_session(const std::string& path);

}  // namespace fov
