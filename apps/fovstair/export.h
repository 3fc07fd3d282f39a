// Session files exported for the tools labs already use: PsychoPy-style per-trial CSV and
// BIDS behavioural data (_beh.tsv with its JSON sidecar). Mapping in docs/fovstair.md.
#pragma once

#include <string>
#include <vector>

#include "fov/labels.h"
#include "session.h"

namespace fov {

enum class export_format : uint8_t { psychopy, bids };
inline constexpr label_table<export_format, 2> export_format_labels = {{"psychopy", export_format::psychopy},
                                                                       {"bids", export_format::bids}};

struct export_options {
  export_format format = export_format::psychopy;
  std::string out_dir = "export";
  std::string task = "foveation";  // BIDS task label (letters and digits)
};

// A BIDS label for `text`: its letters and digits ("P-03" -> "P03"); "" when none are left.
std::string bids_label(const std::string& text);

// The files the sessions become, written atomically under out_dir; returns their paths.
// Throws std::runtime_error before writing anything when two subjects share a BIDS label
// or a session holds no trials.
std::vector<std::string> export_sessions(const std::vector<session_data>& sessions, const std::vector<std::string>& paths,
                                         const export_options& o);

}  // namespace fov
