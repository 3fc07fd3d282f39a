#include "commands.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "../common/cli.h"
#include "../common/gaze_flags.h"
#include "../common/gaze_source.h"
#include "fov/renderer.h"
#include "../common/window.h"
#include "analysis.h"
#include "export.h"
#include "fov/pointset_io.h"
#include "fov/random.h"
#include "fov/scene.h"
#include "live_trial.h"
#include "observer.h"
#include "protocol.h"
#include "session.h"
#include "simulation.h"
#include "staircase_plot.h"

namespace fov {

namespace {


using json = nlohmann::json;
namespace fs = std::filesystem;

std::string now_iso() {
  const std::time_t t = std::time(nullptr);
  char buffer[32];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buffer;
}

}  // namespace

int run_session(const run_options& o) {
  const std::string &protocol_path = o.protocol, &subject = o.subject, &out_dir = o.out_dir, &observer_spec = o.observer;
  const std::string& script_keys = o.script_keys;
  std::string session = o.session;
  const bool resume = o.resume, gaze_mouse = o.gaze_mouse;
  const uint64_t stop_after = o.stop_after;
  gaze_options gaze_flags = o.gaze;
  require_valid(gaze_flags);
  if (gaze_flags.sources() + gaze_mouse > 1) throw usage_error("choose one gaze source");
  if (!(o.screen_ppd == 0 || (o.screen_ppd >= 1 && o.screen_ppd <= 1000)))
    throw usage_error(fmt::format("--screen-ppd {}: must lie in 1..1000 pixels per degree (or be 0: frames 1:1)", o.screen_ppd));
  if ((o.screen_ppd > 0 || o.fullscreen) && !o.observer.empty())
    throw usage_error("--screen-ppd and --fullscreen are for a window; --observer answers without one");
  presentation how;
  // Lab IDs as labs write them (P-03, sub-07, S_12): letters, digits, _ and -, starting with
  // a letter or digit (the session file is SUBJECT-SESSION.jsonl).
  if (!std::regex_match(subject, std::regex("[A-Za-z0-9][A-Za-z0-9_-]{0,31}")))
    throw usage_error(fmt::format("--subject '{}': use 1-32 letters, digits, _ or -, starting with a letter or digit", subject));
  // --out is made only when the session file is (a run that cannot start leaves nothing).
  require_output_dir("--out", out_dir);
  std::error_code ec;
  const bool out_exists = fs::is_directory(out_dir, ec);
  // Session number: the next free one, or (--resume) the newest. Session numbers have at
  // most six digits (--session); other names in the folder are not sessions.
  if (session.empty()) {
    int newest = 0;
    const std::regex name(subject + "-([0-9]{1,6})\\.jsonl");
    if (out_exists)
      for (const auto& e : fs::directory_iterator(out_dir, ec)) {
        std::smatch m;
        const std::string file = e.path().filename().string();
        if (std::regex_match(file, m, name)) newest = std::max(newest, std::stoi(m[1]));
      }
    if (resume && newest == 0) throw std::runtime_error(fmt::format("--resume: no session of {} in {}", subject, out_dir));
    session = std::to_string(resume ? newest : newest + 1);
  }
  if (!std::regex_match(session, std::regex("[0-9]{1,6}"))) throw usage_error(fmt::format("--session '{}': a number", session));
  const std::string path = (fs::path(out_dir) / (subject + "-" + session + ".jsonl")).string();

  if (!resume && fs::exists(path))
    throw std::runtime_error(fmt::format("{}: the session exists; continue it with --resume or choose another --session", path));
  std::optional<observer_model> observer;
  if (!observer_spec.empty()) {
    try {
      observer = parse_observer(observer_spec);
    } catch (const std::invalid_argument& e) {
      throw usage_error(fmt::format("--observer {}", e.what()));
    }
  }
  json header;
  std::vector<json> done;
  size_t practiced = 0;  // practice trials the session file already holds
  std::optional<session_file> file;
  std::string protocol_text;
  if (resume) {
    if (!protocol_path.empty()) std::cerr << "fovstair: note: --resume uses the protocol stored in the session, not --protocol\n";
    practiced = read_session(path).practice.size();  // a quit before the first trial resumes the practice
    file.emplace(session_file::resume(path, subject, header, done));
    protocol_text = header.at("protocol_text").get<std::string>();  // read_session checked the header's fields
    if (header.contains("observer") && header["observer"].is_string() && !observer)
      observer = parse_observer(header["observer"].get<std::string>());
  } else {
    if (protocol_path.empty()) throw usage_error("run: --protocol is required");
    protocol_text = read_protocol_text(protocol_path);
  }
  const stair_protocol p = parse_protocol(protocol_text, resume ? path + " (stored protocol)" : protocol_path);
  stair_session state(p, subject);
  // Replay the answers (read_session checked each trial against the protocol's plan).
  for (const json& t : done) state.record(state.next(), t.at("detected").get<bool>());
  // A person: the window, the scene and the point sets.
  std::unique_ptr<view_window> window;
  std::unique_ptr<fov::renderer> stimulus;
  std::unique_ptr<gaze_source> gaze;
  std::unique_ptr<gaze_conditioner> conditioner;
  std::map<double, std::shared_ptr<const pointset>> sets;
  if (!observer) {
    for (double s : reachable_scales(p))
      if (!fs::exists(pointset_path(p, s)))
        throw std::runtime_error(fmt::format(
            "{}: missing (the staircase can reach s = {:.2f}); make the family with: fovgen sweep --display {} --scales "
            "{:.1f}:{:.1f}:{} -o {}",
            pointset_path(p, s), s, p.display, p.scale_min, p.scale_max, sweep_step(p), p.points_dir));
    auto first = std::make_shared<const pointset>(load_pointset(pointset_path(p, state.next().scale)));
    const display_geometry& d = first->model.display;
    std::shared_ptr<const scene> scn = load_scene(p.scene, p.env_light);
    stimulus = std::make_unique<fov::renderer>(scn, stimulus_params(p, p.conditions.front()));
    how.scale = o.screen_ppd > 0 ? o.screen_ppd / pixels_per_degree(d) : 1;
    how.fullscreen = o.fullscreen;
    window = std::make_unique<view_window>("fovstair " + p.name, d.width, d.height, how);
    const int sw = int(std::lround(d.width * how.scale)), sh = int(std::lround(d.height * how.scale));
    if (sw > window->screen().width || sh > window->screen().height)
      std::cerr << fmt::format("fovstair: warning: the frame scaled x{:.3g} is {}x{} pixels and the window {}x{}: its edges "
                               "are cut\n", how.scale, sw, sh, window->screen().width, window->screen().height);
    gaze = open_gaze(gaze_flags, d.width, d.height);
    if (gaze_mouse) gaze = std::make_unique<mouse_gaze>(d.width, d.height);
    if (gaze) conditioner = std::make_unique<gaze_conditioner>(gaze_flags.conditioning, d, gaze->live());
    sets[state.next().scale] = first;
  }

  // The session file is created only once the window, scene and sets are ready, so a
  // run that cannot start leaves nothing behind.
  if (!resume) {
    make_output_dir(out_dir);
    std::vector<std::string> order;
    for (uint32_t c : state.order()) order.push_back(p.conditions[c].name);
    header = {{"type", "session"},     {"fovstair", 1},          {"subject", subject},
              {"session", session},    {"protocol_file", protocol_path}, {"protocol_text", protocol_text},
              {"condition_order", order}, {"started", now_iso()},
              {"observer", observer ? json(observer_text(*observer)) : json(nullptr)}};
    if (!observer)
      header["presentation"] = {{"scale", how.scale}, {"fullscreen", how.fullscreen}, {"screen_ppd", o.screen_ppd},
                                {"screen", {window->screen().width, window->screen().height}}};
    file.emplace(session_file::create(path, header));
  } else {
    std::cerr << fmt::format("fovstair: resuming {} at trial {}\n", path, done.size());
  }

  // One showing in the window: the answer and the record fields it adds. `key_index`
  // picks the --script-keys answer.
  auto show_live = [&](const trial_plan& t, size_t key_index, trial_answer& a) -> json {
    auto& set = sets[t.scale];
    if (!set) {
      if (sets.size() > 3) sets.erase(sets.begin() == sets.find(t.scale) ? std::next(sets.begin()) : sets.begin());
      set = std::make_shared<const pointset>(load_pointset(pointset_path(p, t.scale)));
    }
    stimulus->use_pointset(set);
    live_context ctx{p, *stimulus, *window, gaze.get(), conditioner.get(), {}};
    if (!script_keys.empty()) {  // testing: this trial's answer from the script
      if (key_index >= script_keys.size()) throw std::runtime_error("--script-keys: ran out of answers");
      ctx.scripted_keys = script_keys.substr(key_index, 1);
    }
    if (auto* m = dynamic_cast<mouse_gaze*>(gaze.get())) {
      double x, y;
      if (window->mouse(x, y)) m->set(x, y);
    }
    a = run_live_trial(ctx, t, *set);
    return {{"response", a.response},
            {"rt_ms", a.rt_ms},
            {"gaze", {{"source", gaze ? gaze->name() : "fixation"}, {"samples", a.gaze_samples}, {"clamped", a.gaze_clamped},
                      {"mean", {a.gaze_mean[0], a.gaze_mean[1]}}, {"sd", {a.gaze_sd[0], a.gaze_sd[1]}},
                      {"trace", a.gaze_trace}}},
            {"fixation_max_deg", a.fixation_max_deg},
            {"fixation_broken", a.fixation_broken},
            {"mean_frame_ms", a.mean_frame_ms}};
  };
  auto quit_message = [&](uint64_t at) {
    std::cerr << fmt::format("fovstair: quit at trial {}; continue with: fovstair run --subject {} --session {} --out {} --resume\n",
                             at, subject, session, out_dir);
    return 0;
  };
  size_t practice_keys = 0;  // --script-keys answers used by practice trials
  if (!observer) {
    const display_geometry& d = sets.begin()->second->model.display;
    live_context ctx{p, *stimulus, *window, gaze.get(), conditioner.get(), script_keys.empty() ? "" : "x"};
    if (!show_instructions(ctx, d.width, d.height)) return quit_message(done.size());
    // Practice, before the first trial only (a session quit during its practice resumes it):
    // recorded, never given to a procedure.
    for (uint32_t i = uint32_t(practiced); done.empty() && i < p.practice.trials; ++i) {
      trial_plan t;
      t.index = i;
      t.condition = state.order()[i % state.order().size()];
      t.scale = practice_scale(p, i);
      const auto& f = p.fixations.front();
      t.fixation_x = f.first, t.fixation_y = f.second;
      t.foveated_interval = uint32_t(rng(stream_seed(p.seed, subject_number(subject), 0x9ac7 + i)).next() >> 63);
      trial_answer a;
      json r = show_live(t, practice_keys++, a);
      if (a.quit) return quit_message(0);
      r.update({{"type", "practice"}, {"index", i}, {"condition", p.conditions[t.condition].name}, {"scale", t.scale},
                {"detected", a.detected}, {"time", now_iso()}});
      if (p.mode == stair_mode::two_afc) r["foveated_interval"] = t.foveated_interval + 1;
      file->append(r);
      if (p.practice.feedback)
        show_feedback(ctx, d.width, d.height,
                      p.mode == stair_mode::two_afc ? (a.detected ? "Correct." : fmt::format("Wrong: it was {}.", t.foveated_interval + 1))
                                                    : "That one was foveated.");
    }
  }
  uint64_t this_run = 0;
  uint32_t repeats = 0;  // of the trial on screen, after broken fixation
  while (!state.finished()) {
    const trial_plan t = state.next();
    bool detected = false;
    json extra;
    if (observer) {
      detected = observer_answer(*observer, stream_seed(p.seed, subject_number(subject)), t.index, t.scale,
                                      t.is_catch, p.mode == stair_mode::two_afc);
      extra = {{"response", p.mode == stair_mode::yes_no ? (detected ? "yes" : "no")
                                                               : std::to_string(detected ? t.foveated_interval + 1 : 2 - t.foveated_interval)},
               {"rt_ms", nullptr}};
    } else {
      trial_answer a;
      extra = show_live(t, practice_keys + this_run, a);
      if (a.quit) return quit_message(t.index);
      detected = a.detected;
      if (a.fixation_broken && p.fixation.action == fixation_action::repeat && repeats < p.fixation.max_repeats) {
        // Shown again: the answer is kept in a "repeat" record, never given to the procedure.
        ++repeats;
        json r = {{"type", "repeat"}, {"index", t.index}, {"condition", p.conditions[t.condition].name}, {"scale", t.scale},
                  {"detected", detected}, {"reason", fmt::format("gaze {:.2f} deg from the fixation target (radius {:g})",
                                                                  a.fixation_max_deg, p.fixation.radius_deg)}};
        r.update(extra);
        r["time"] = now_iso();
        file->append(r);
        continue;
      }
      repeats = 0;
    }
    const staircase::step step = state.record(t, detected);
    json record = trial_record(p, t, detected, step);
    record.update(extra);
    record["time"] = now_iso();
    file->append(record);  // written and fsync'ed before the next trial
    ++this_run;
    if (stop_after > 0 && this_run >= stop_after) std::_Exit(3);  // as a crash would: no end record
  }
  file->append({{"type", "end"}, {"time", now_iso()}});
  for (uint32_t c : state.order()) {
    const stair_series& s = state.series(c);
    double mean = 0;
    for (double v : s.thresholds()) mean += v / double(s.thresholds().size());
    fmt::print("{}: {} trials, thresholds [{}], mean {:.3f}{}\n", p.conditions[c].name, s.trials(),
               fmt::join(s.thresholds(), ", "), mean, s.complete() ? "" : " (incomplete: max_trials reached)");
  }
  fmt::print("data: {}\n", path);
  return 0;
}

int simulate(const simulate_options& so) {
  const std::string &protocol_path = so.protocol, &observer_spec = so.observer;
  const uint32_t runs = so.runs;
  const bool as_json = so.json;
  const rule_overrides& o = so.overrides;
  if (protocol_path.empty()) throw usage_error("simulate: --protocol is required");
  if (observer_spec.empty()) throw usage_error("simulate: --observer is required");
  if (runs < 1 || runs > max_simulation_runs) throw usage_error(fmt::format("--runs must lie in 1..{}", max_simulation_runs));
  stair_protocol base = load_protocol(protocol_path);
  // -1 means not given; anything else (NaN too) replaces the protocol's value and is checked.
  if (o.step != -1) base.rule.step = o.step;
  if (o.initial_step != -1) base.rule.initial_step = o.initial_step;
  if (o.start != -1) base.scale_start = o.start;
  if (o.thresholds >= 0) base.rule.thresholds = uint32_t(o.thresholds);
  if (o.discard >= 0) base.rule.discard_reversals = uint32_t(o.discard);
  if (!(base.rule.step >= 0.01) || !(base.rule.initial_step >= base.rule.step) || !(base.rule.initial_step <= max_protocol_scale))
    throw usage_error(fmt::format("--step must be at least 0.01, --initial-step at least --step and at most {}", max_protocol_scale));
  if (!(base.scale_start >= base.scale_min && base.scale_start <= base.scale_max))
    throw usage_error(fmt::format("--start must lie in the protocol's scales {}..{}", base.scale_min, base.scale_max));
  if (base.rule.thresholds < 1 || base.rule.thresholds > std::min(base.rule.max_trials, max_protocol_thresholds))
    throw usage_error(fmt::format("--thresholds must lie in 1..{} (the protocol's max_trials, at most {})", base.rule.max_trials,
                                  max_protocol_thresholds));
  if (base.rule.discard_reversals > max_protocol_thresholds)
    throw usage_error(fmt::format("--discard must lie in 0..{}", max_protocol_thresholds));
  observer_model m;
  try {
    m = parse_observer(observer_spec);
  } catch (const std::invalid_argument& e) {
    throw usage_error(fmt::format("--observer {}", e.what()));
  }
  if (!(m.threshold >= base.scale_min && m.threshold <= base.scale_max))
    throw usage_error(fmt::format("--observer: threshold {} lies outside the protocol's scales {}..{}; the staircase cannot "
                                  "reach it", m.threshold, base.scale_min, base.scale_max));
  const bool two_afc = base.mode == stair_mode::two_afc;
  // The procedures to run: the protocol's, or those --procedure names (the others with
  // their defaults: a protocol holds settings for its own procedure only).
  std::vector<stair_procedure> procedures;
  for (const std::string& label : so.procedures) {
    if (label == "all") {
      for (const auto& [l, v] : stair_procedure_labels) procedures.push_back(v);
      continue;
    }
    stair_procedure v;
    if (!parse_label(stair_procedure_labels, label, v))
      throw usage_error(fmt::format("--procedure: '{}' is not one of {}, all", printable(label), label_list(stair_procedure_labels)));
    procedures.push_back(v);
  }
  if (procedures.empty()) procedures.push_back(base.procedure);
  const bool overridden = o.step != -1 || o.initial_step != -1 || o.thresholds >= 0 || o.discard >= 0;
  json results = json::array();
  for (stair_procedure proc : procedures) {
    stair_protocol p = base;
    p.procedure = proc;
    if (proc != stair_procedure::up_down && overridden)
      throw usage_error("--step, --initial-step, --thresholds and --discard change the up-down rule; QUEST and QUEST+ have none");
    const simulation_result r = simulate_rule(p, m, runs);
    const bool none = r.estimates.empty();
    const double rmse = none ? 0 : std::sqrt(r.sd * r.sd * double(r.estimates.size() - 1) / double(r.estimates.size()) +
                                             (r.mean - r.target_scale) * (r.mean - r.target_scale));
    json j = {{"procedure", label_of(stair_procedure_labels, proc)},
              {"true_threshold", m.threshold},
              {"estimate_mean", none ? json(nullptr) : json(r.mean)},
              {"estimate_sd", none ? json(nullptr) : json(r.sd)},
              {"bias", none ? json(nullptr) : json(r.mean - m.threshold)},
              {"bias_from_target", none ? json(nullptr) : json(r.mean - r.target_scale)},
              {"rmse_from_target", none ? json(nullptr) : json(rmse)},
              {"runs", runs},
              {"series", r.series},
              {"incomplete_series", r.incomplete},
              {"mean_trials_per_run", double(r.trials) / runs},
              {"mean_trials_per_series", double(r.trials) / double(std::max<uint64_t>(1, r.series))},
              {"mode", two_afc ? "2afc" : "yes-no"},
              {"target_probability", r.target_probability},
              {"target_scale", r.target_scale},
              {"observer", observer_text(m)}};
    if (proc == stair_procedure::up_down)
      j["rule"] = {{"up", p.rule.up}, {"down", p.rule.down}, {"initial_step", p.rule.initial_step}, {"step", p.rule.step},
                   {"thresholds", p.rule.thresholds}, {"discard_reversals", p.rule.discard_reversals}, {"start", p.scale_start}};
    results.push_back(j);
    if (as_json) continue;
    const char* name = label_of(stair_procedure_labels, proc);
    if (none)
      fmt::print("{}: true threshold {:.3f}: no estimate, no series of {} runs recorded a threshold; {} incomplete\n", name,
                 m.threshold, runs, r.incomplete);
    else
      fmt::print("{}: true threshold {:.3f}: estimate {:.3f} +- {:.3f} (bias {:+.3f}) over {} series of {} runs, {:.1f} trials "
                 "per series (catch trials included); {} incomplete\n",
                 name, m.threshold, r.mean, r.sd, r.mean - m.threshold, r.estimates.size(), runs,
                 double(r.trials) / double(std::max<uint64_t>(1, r.series)), r.incomplete);
    fmt::print("{}: aims at P(detect) = {:.3f}, which this observer reaches at s = {:.3f} (estimate - that {:+.3f}, rmse {:.3f})\n",
               name, r.target_probability, r.target_scale, none ? 0.0 : r.mean - r.target_scale, rmse);
  }
  if (as_json) std::cout << (results.size() == 1 ? results[0] : json{{"procedures", results}}).dump(2) << "\n";
  return 0;
}

namespace {
json p_json(double p) { return std::isfinite(p) ? json(p) : json(nullptr); }
}  // namespace

int analyze(const analyze_options& o) {
  const std::vector<std::string>& inputs = o.inputs;
  const std::string &thresholds_csv = o.thresholds, &out_csv = o.out_csv;
  std::string plots_dir = o.plots;
  const bool as_json = o.json;
  std::vector<threshold_value> values;
  std::vector<session_data> sessions;
  // Outputs checked before anything is read or written: never one of the inputs.
  std::vector<std::string> all_inputs = inputs;
  all_inputs.push_back(thresholds_csv);
  require_output("--out-csv", out_csv, all_inputs);
  if (!plots_dir.empty()) require_output_dir("--plots", plots_dir);
  std::vector<psychometric_family> families;
  for (const std::string& f : o.fits) {
    psychometric_family v;
    if (f == "none") continue;
    if (!parse_label(psychometric_family_labels, f, v))
      throw usage_error(fmt::format("--fit: '{}' is not one of {}, none", printable(f), label_list(psychometric_family_labels)));
    if (std::find(families.begin(), families.end(), v) == families.end()) families.push_back(v);
  }
  if (o.bootstrap > max_psychometric_bootstrap)
    throw usage_error(fmt::format("--bootstrap must lie in 0..{}", max_psychometric_bootstrap));
  if (!thresholds_csv.empty()) {
    if (!inputs.empty()) throw usage_error("analyze: give session files or --thresholds, not both");
    values = read_thresholds_csv(thresholds_csv);
  } else {
    if (inputs.empty()) throw usage_error("analyze: no session files (or --thresholds FILE)");
    for (const std::string& f : inputs) sessions.push_back(read_session(f));
    values = thresholds_from_sessions(sessions);
    if (values.empty()) throw std::runtime_error("the sessions hold no recorded thresholds yet");
  }
  const threshold_analysis a = analyze_thresholds(values);
  const std::string mix = simulated_mix_warning(sessions, inputs);
  if (!mix.empty()) fmt::print(stderr, "fovstair: warning: {}\n", mix);
  // Psychometric fits per subject and condition, from the sessions' trials.
  struct fitted {
    psychometric_data data;
    std::vector<psychometric_fit> fits;
    std::string skipped;
  };
  std::vector<fitted> fits;
  for (psychometric_data& d : psychometric_data_from_sessions(sessions)) {
    if (families.empty()) break;
    fitted f{std::move(d), {}, ""};
    if (f.data.levels.size() < 2) {
      f.skipped = "trials at fewer than two scales";
    } else {
      fit_options fo;
      fo.guess = f.data.guess, fo.bootstrap = o.bootstrap;
      fo.seed = stream_seed(subject_number(f.data.subject), text_seed(f.data.condition));  // reruns agree
      for (psychometric_family fam : families) f.fits.push_back(fit_psychometric(f.data.levels, fam, fo));
    }
    fits.push_back(std::move(f));
  }
  if (!out_csv.empty()) write_thresholds_csv(values, out_csv);
  // Plots, only where --plots says: one per series, and one per subject and condition.
  std::vector<std::string> plots;
  if (!sessions.empty() && !plots_dir.empty()) {
    make_output_dir(plots_dir);
    for (const session_data& s : sessions) {
      const stair_protocol p = parse_protocol(s.header.at("protocol_text").get<std::string>(), "stored protocol");  // checked
      for (const stair_condition& c : p.conditions) {
        std::vector<json> series;
        for (const json& t : s.trials)
          if (t.value("condition", "") == c.name) series.push_back(t);
        if (series.empty()) continue;
        const std::string name = fmt::format("{}-{}-{}.png", s.header.value("subject", "?"), s.header.value("session", "?"), c.name);
        const std::string path = (fs::path(plots_dir) / name).string();
        write_staircase_plot(series, fmt::format("{} session {}: {}", s.header.value("subject", "?"),
                                                      s.header.value("session", "?"), c.name),
                                  p.scale_min, p.scale_max, path);
        plots.push_back(path);
      }
    }
    double lo = 10, hi = 0;
    for (const session_data& s : sessions) {
      const stair_protocol p = parse_protocol(s.header.at("protocol_text").get<std::string>(), "stored protocol");
      lo = std::min(lo, p.scale_min), hi = std::max(hi, p.scale_max);
    }
    for (const fitted& f : fits) {
      if (f.fits.empty()) continue;
      const std::string path = (fs::path(plots_dir) / fmt::format("{}-{}-psychometric.png", f.data.subject, f.data.condition)).string();
      write_psychometric_plot(f.data, f.fits, fmt::format("{}: {} ({} trials)", f.data.subject, f.data.condition, f.fits[0].trials),
                              lo, hi, path);
      plots.push_back(path);
    }
  }
  // Catch trials: how often "yes" when nothing was foveated.
  uint64_t catches = 0, false_alarms = 0;
  for (const session_data& s : sessions)
    for (const json& t : s.trials)
      if (t.value("catch", false)) ++catches, false_alarms += t.value("detected", false);

  json j;
  for (const auto& c : a.conditions) j["conditions"][c.name] = {{"n", c.n}, {"mean", c.mean}, {"sd", p_json(c.sd)}, {"values", c.values}};
  if (a.anova) j["anova"] = {{"F", a.F}, {"df1", a.df1}, {"df2", a.df2}, {"p", a.p}, {"on", "log subject means"}};
  else j["anova"] = nullptr, j["anova_note"] = a.anova_note;
  for (const fitted& f : fits) {
    json entry = {{"subject", f.data.subject}, {"condition", f.data.condition}, {"mode", f.data.two_afc ? "2afc" : "yes-no"},
                  {"guess", f.data.guess}, {"levels", f.data.levels.size()}};
    if (!f.skipped.empty()) entry["skipped"] = f.skipped;
    for (const psychometric_fit& pf : f.fits)
      entry["fits"].push_back({{"family", label_of(psychometric_family_labels, pf.family)}, {"alpha", pf.params.alpha},
                               {"alpha_interval", {p_json(pf.alpha_lo), p_json(pf.alpha_hi)}},
                               {"alpha_interval_open", {pf.bootstrap > 1 && pf.low_open(), pf.bootstrap > 1 && pf.high_open()}},
                               {"alpha_bounds", {pf.alpha_min, pf.alpha_max}}, {"beta", pf.params.beta},
                               {"lapse", pf.params.lapse}, {"log_likelihood", pf.log_likelihood}, {"deviance", pf.deviance},
                               {"trials", pf.trials}, {"bootstrap", pf.bootstrap}});
    j["psychometric"].push_back(entry);
  }
  if (!mix.empty()) j["warnings"].push_back(mix);
  for (const auto& pc : a.pairs)
    j["pairwise"].push_back({{"a", pc.a}, {"b", pc.b}, {"t", pc.t}, {"df", pc.df}, {"p", pc.p}, {"p_bonferroni", pc.p_bonferroni},
                             {"paired_n", pc.paired_n}, {"paired_t", pc.paired_t}, {"paired_p", p_json(pc.paired_p)}});
  for (const auto& [subject, conditions] : a.values)
    for (const auto& [condition, v] : conditions) {
      double mean = 0;
      for (double x : v) mean += x / double(v.size());
      j["subjects"][subject][condition] = {{"thresholds", v}, {"mean", mean}};
    }
  if (!sessions.empty()) j["catch_trials"] = {{"n", catches}, {"false_alarms", false_alarms}};
  if (!plots.empty()) j["plots"] = plots;
  if (as_json) {
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{:<10} {:>4} {:>8} {:>8} {:>7}\n", "condition", "n", "mean", "sd", "values");
  for (const auto& c : a.conditions)
    fmt::print("{:<10} {:>4} {:>8.3f} {:>8} {:>7}\n", c.name, c.n, c.mean, std::isfinite(c.sd) ? fmt::format("{:.3f}", c.sd) : "-",
               c.values);
  if (a.values.size() == 1)
    for (const auto& [condition, v] : a.values.begin()->second)
      fmt::print("  {} {}: thresholds [{:.3f}]\n", a.values.begin()->first, condition, fmt::join(v, ", "));
  if (a.anova) fmt::print("one-way ANOVA on log subject means: F({:g}, {:g}) = {:.3f}, p = {:.3f}\n", a.df1, a.df2, a.F, a.p);
  else fmt::print("no ANOVA: {}\n", a.anova_note);
  if (!fits.empty())
    fmt::print("psychometric fits (maximum likelihood; guess fixed; lapse in [0, 0.06]{}):\n",
               o.bootstrap ? fmt::format("; alpha's 95 % interval from {} bootstrap samples", o.bootstrap) : "");
  for (const fitted& f : fits) {
    if (!f.skipped.empty()) fmt::print("  {} {}: not fitted, {}\n", f.data.subject, f.data.condition, f.skipped);
    for (const psychometric_fit& pf : f.fits)
      fmt::print("  {} {} {:<8} alpha {:.3f} {}  beta {:.3g}  lapse {:.3f}  guess {:.3f}  deviance {:.2f}  ({} trials, {} scales)\n",
                 f.data.subject, f.data.condition, label_of(psychometric_family_labels, pf.family), pf.params.alpha,
                 pf.bootstrap > 1 ? fmt::format("[{}{:.3f}, {}{:.3f}]", pf.low_open() ? "<" : "", pf.alpha_lo,
                                                pf.high_open() ? ">" : "", pf.alpha_hi)
                                  : std::string("(no interval)"),
                 pf.params.beta, pf.params.lapse, pf.params.guess, pf.deviance, pf.trials, f.data.levels.size());
  if (std::any_of(fits.begin(), fits.end(), [](const fitted& f) {
        return std::any_of(f.fits.begin(), f.fits.end(),
                           [](const psychometric_fit& p) { return p.bootstrap > 1 && (p.low_open() || p.high_open()); });
      }))
    fmt::print("  (< or >: the interval reaches alpha's bound, the tested scales widened by their range: the data do not "
               "bound it on that side)\n");
  }
  for (const auto& pc : a.pairs)
    fmt::print("  {} vs {}: LSD t({:g}) = {:+.3f}, p = {:.3f} (Bonferroni {:.3f}); paired t({}) = {:+.3f}, p = {:.3f}\n", pc.a,
               pc.b, pc.df, pc.t, pc.p, pc.p_bonferroni, pc.paired_n > 0 ? pc.paired_n - 1 : 0, pc.paired_t, pc.paired_p);
  if (catches) fmt::print("catch trials: {} of {} answered yes\n", false_alarms, catches);
  for (const std::string& p : plots) fmt::print("plot: {}\n", p);
  return 0;
}

int export_command(const export_command_options& o) {
  export_options e;
  if (!parse_label(export_format_labels, o.format, e.format))
    throw usage_error(fmt::format("--format: '{}' is not {}", printable(o.format), label_alternatives(export_format_labels)));
  if (o.task.empty() || bids_label(o.task) != o.task || o.task.size() > 64)
    throw usage_error(fmt::format("--task: '{}' must be 1-64 letters and digits (a BIDS label)", printable(o.task)));
  if (o.inputs.empty()) throw usage_error("export: no session files");
  require_output_dir("--out", o.out_dir);
  e.out_dir = o.out_dir, e.task = o.task;
  std::vector<session_data> sessions;
  for (const std::string& f : o.inputs) sessions.push_back(read_session(f));
  for (const std::string& path : export_sessions(sessions, o.inputs, e)) fmt::print("wrote {}\n", path);
  return 0;
}

int validate_protocol(const std::string& protocol) {
  const stair_protocol p = load_protocol(protocol);
  std::string procedure;
  if (p.procedure == stair_procedure::up_down)
    procedure = fmt::format("rule {}-up/{}-down, {} thresholds per condition", p.rule.up, p.rule.down, p.rule.thresholds);
  else if (p.procedure == stair_procedure::quest)
    procedure = fmt::format("QUEST at {:.0f} % {}, {} trials per condition{}", 100 * p.quest.p_threshold,
                            p.mode == stair_mode::two_afc ? "correct" : "detected", p.quest.max_trials,
                            p.quest.stop_interval > 0 ? " or fewer (stop_interval)" : "");
  else
    procedure = fmt::format("QUEST+ over {} parameter combinations, {} trials per condition{}",
                            quest_plus(p.quest_plus, reachable_scales(p), p.mode == stair_mode::two_afc).parameter_combinations(),
                            p.quest_plus.max_trials, p.quest_plus.stop_interval > 0 ? " or fewer (stop_interval)" : "");
  fmt::print("{}: {} conditions, scales {:.2f}..{:.2f}, {}\n", protocol, p.conditions.size(), p.scale_min, p.scale_max, procedure);
  if (!p.env_light.empty())  // a session would stop when its scene loads
    if (const std::string why = env_image_problem(p.env_light); !why.empty())
      throw std::runtime_error(fmt::format("{}: env_light {}: {}", protocol, p.env_light, why));
  int missing = 0;
  for (double s : reachable_scales(p)) {
    const std::string f = pointset_path(p, s);
    if (!fs::exists(f)) ++missing, fmt::print("  missing: {}\n", f);
  }
  if (missing)  // a session would stop at the first missing set: not valid for a run
    throw std::runtime_error(fmt::format("{}: {} point sets missing (listed above); make the family with: fovgen sweep "
                                         "--display {} --scales {:.1f}:{:.1f}:{} -o {}",
                                         protocol, missing, p.display, p.scale_min, p.scale_max, sweep_step(p), p.points_dir));
  fmt::print("all point sets present\n");
  return 0;
}

}  // namespace fov
