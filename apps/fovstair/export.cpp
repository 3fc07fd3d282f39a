#include "export.h"

#include <cctype>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "fov/files.h"

namespace fov {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

// A value for a CSV or TSV cell: text without the separator, quotes or line breaks.
std::string cell(const json& v, const std::string& missing) {
  if (v.is_null()) return missing;
  if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number()) return fmt::format("{:.6g}", v.get<double>());
  std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  for (char& c : s)
    if (c == ',' || c == '\t' || c == '"' || c == '\n' || c == '\r') c = '_';
  return s;
}

json field(const json& t, const char* key) { return t.contains(key) ? t[key] : json(nullptr); }

json estimate_of(const json& t) {
  const auto it = t.find("estimate");
  return it != t.end() && it->is_object() && it->contains("threshold") ? (*it)["threshold"] : json(nullptr);
}

json seconds(const json& ms) { return ms.is_number() ? json(ms.get<double>() / 1000) : json(nullptr); }

void write_text(const std::string& path, const std::string& text) {
  make_output_dir(fs::path(path).parent_path().string());
  write_file_atomic(path, text.data(), text.size());
}

}  // namespace

std::string bids_label(const std::string& text) {
  std::string out;
  for (char c : text)
    if (std::isalnum(static_cast<unsigned char>(c))) out += c;
  return out;
}

std::vector<std::string> export_sessions(const std::vector<session_data>& sessions, const std::vector<std::string>& paths,
                                         const export_options& o) {
  // Everything is checked before anything is written.
  std::map<std::string, std::string> label_owner;
  for (size_t i = 0; i < sessions.size(); ++i) {
    const std::string subject = sessions[i].header.value("subject", "");
    const std::string where = i < paths.size() ? paths[i] : "session";
    if (sessions[i].trials.empty()) throw std::runtime_error(fmt::format("{}: no trials to export", where));
    if (o.format != export_format::bids) continue;
    const std::string label = bids_label(subject);
    if (label.empty()) throw std::runtime_error(fmt::format("{}: subject '{}' has no letters or digits for a BIDS label", where, printable(subject)));
    const auto [it, fresh] = label_owner.emplace(label, subject);
    if (!fresh && it->second != subject)
      throw std::runtime_error(fmt::format("{}: subjects '{}' and '{}' would both be BIDS sub-{}", where, printable(it->second),
                                           printable(subject), label));
  }
  std::vector<std::string> written;
  if (o.format == export_format::bids && !fs::exists(fs::path(o.out_dir) / "dataset_description.json")) {
    const json d = {{"Name", "fovstair sessions"}, {"BIDSVersion", "1.9.0"}, {"DatasetType", "raw"},
                    {"GeneratedBy", {{{"Name", "fovstair export"}}}}};
    const std::string path = (fs::path(o.out_dir) / "dataset_description.json").string();
    write_text(path, d.dump(2) + "\n");
    written.push_back(path);
  }
  for (const session_data& s : sessions) {
    const std::string subject = s.header.value("subject", "?"), session = s.header.value("session", "?");
    const stair_protocol p = parse_protocol(s.header.at("protocol_text").get<std::string>(), "stored protocol");  // checked
    const bool two_afc = p.mode == stair_mode::two_afc;
    if (o.format == export_format::psychopy) {
      // Named as PsychoPy's Builder names its data files (participant_expName), one row per
      // trial with the staircase handlers' column names.
      std::string text = "participant,session,label,thisN,thisTrialN,intensity,response,reversal,catch,key,rt,estimate,date\n";
      for (const json& t : s.trials)
        text += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{}\n", cell(subject, ""), cell(session, ""),
                            cell(field(t, "condition"), ""), cell(field(t, "index"), ""), cell(field(t, "series_trial"), ""),
                            cell(field(t, "scale"), ""), cell(field(t, "detected"), ""), cell(field(t, "reversal"), ""),
                            cell(field(t, "catch"), ""), cell(field(t, "response"), ""), cell(seconds(field(t, "rt_ms")), ""),
                            cell(estimate_of(t), ""), cell(field(t, "time"), ""));
      const std::string name = bids_label(p.name).empty() ? "fovstair" : bids_label(p.name);
      const std::string path = (fs::path(o.out_dir) / fmt::format("{}_{}_{}.csv", subject, name, session)).string();
      write_text(path, text);
      written.push_back(path);
      continue;
    }
    const std::string sub = "sub-" + bids_label(subject), ses = "ses-" + bids_label(session);
    const fs::path dir = fs::path(o.out_dir) / sub / ses / "beh";
    const std::string stem = fmt::format("{}_{}_task-{}_beh", sub, ses, o.task);
    std::string text =
        "trial_index\ttrial_type\tseries_trial\tscale\tcatch_trial\tresponse\tdetected\tresponse_time\treversal\tthreshold\t"
        "estimate\tfixation_x\tfixation_y\tfoveated_interval\ttimestamp\n";
    for (const json& t : s.trials) {
      const json fix = field(t, "fixation");
      const bool has_fix = fix.is_array() && fix.size() == 2;
      text += fmt::format("{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n", cell(field(t, "index"), "n/a"),
                          cell(field(t, "condition"), "n/a"), cell(field(t, "series_trial"), "n/a"), cell(field(t, "scale"), "n/a"),
                          cell(field(t, "catch"), "n/a"), cell(field(t, "response"), "n/a"), cell(field(t, "detected"), "n/a"),
                          cell(seconds(field(t, "rt_ms")), "n/a"), cell(field(t, "reversal"), "n/a"),
                          cell(field(t, "threshold"), "n/a"), cell(estimate_of(t), "n/a"),
                          cell(has_fix ? fix[0] : json(nullptr), "n/a"), cell(has_fix ? fix[1] : json(nullptr), "n/a"),
                          cell(field(t, "foveated_interval"), "n/a"), cell(field(t, "time"), "n/a"));
    }
    const std::string procedure = label_of(stair_procedure_labels, p.procedure);
    const json sidecar = {
        {"TaskName", o.task},
        {"TaskDescription", fmt::format("{}: {} ({}), procedure {}. {}", p.name.empty() ? "fovstair protocol" : p.name,
                                        two_afc ? "two-interval forced choice, which interval was foveated?"
                                                : "yes-no, anything unnatural?",
                                        two_afc ? "2afc" : "yes-no", procedure, p.description)},
        {"fovstair_subject", subject},
        {"trial_index", {{"Description", "Trial number in the session, from 0"}}},
        {"trial_type", {{"Description", "Condition (reconstruction method) of the trial"}}},
        {"series_trial", {{"Description", "Trials of this condition's series before this one (catch trials excluded)"}}},
        {"scale", {{"Description", "Scale factor of the point set's spacing (1: acuity-matched; larger: sparser)"}}},
        {"catch_trial", {{"Description", "The reference was shown instead of the foveated frame"},
                         {"Levels", {{"0", "foveated stimulus"}, {"1", "catch trial"}}}}},
        {"response", {{"Description", two_afc ? "Interval chosen as foveated" : "Answer to 'anything unnatural?'"},
                      {"Levels", two_afc ? json{{"1", "first interval"}, {"2", "second interval"}}
                                         : json{{"yes", "noticed foveation"}, {"no", "did not"}}}}},
        {"detected", {{"Description", two_afc ? "The foveated interval was chosen" : "The answer was yes"},
                      {"Levels", {{"0", "no"}, {"1", "yes"}}}}},
        {"response_time", {{"Description", "From stimulus onset to the answer"}, {"Units", "s"}}},
        {"reversal", {{"Description", "The up-down series changed direction on this trial"}, {"Levels", {{"0", "no"}, {"1", "yes"}}}}},
        {"threshold", {{"Description", "Threshold value this trial recorded (up-down: a counted reversal; QUEST/QUEST+: the final estimate)"}}},
        {"estimate", {{"Description", "QUEST/QUEST+ posterior threshold estimate after this trial (scale)"}}},
        {"fixation_x", {{"Description", "Fixation target, normalised screen x (0 left, 1 right)"}}},
        {"fixation_y", {{"Description", "Fixation target, normalised screen y (0 top, 1 bottom)"}}},
        {"foveated_interval", {{"Description", "2AFC: the interval that showed the foveated frame"}}},
        {"timestamp", {{"Description", "UTC time the trial was recorded (ISO 8601, whole seconds)"}}}};
    const std::string tsv = (dir / (stem + ".tsv")).string(), side = (dir / (stem + ".json")).string();
    write_text(tsv, text);
    write_text(side, sidecar.dump(2) + "\n");
    written.push_back(tsv), written.push_back(side);
  }
  return written;
}

}  // namespace fov
