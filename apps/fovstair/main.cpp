// fovstair: runs the staircase experiment of thesis Sec. 6, simulates observers, analyses data.
#include <CLI/CLI.hpp>

#include "../common/cli.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"fovstair: staircase experiments on foveation thresholds (thesis Sec. 6)"};
  app.require_subcommand(1);
  fov::run_options r;
  fov::simulate_options so;
  fov::analyze_options ao;
  std::string protocol;

  CLI::App* run = app.add_subcommand("run", "Run a session (a window, or --observer for a simulated person)");
  run->add_option("--protocol", r.protocol, "Protocol JSON (docs/fovstair.md)");
  run->add_option("--subject", r.subject, "Subject id, e.g. S07 (its number picks the Latin-square row)")->required();
  run->add_option("--session", r.session, "Session number (default: the next free one; with --resume the newest)");
  run->add_option("--out", r.out_dir, "Data directory (default data/)");
  run->add_flag("--resume", r.resume, "Continue an interrupted session where it stopped");
  run->add_option("--observer", r.observer, "Answer with a simulated observer: logistic:threshold=T,slope=S[,lapse=L]");
  run->add_option("--stop-after", r.stop_after, "Testing: exit abruptly (no end record) after N trials, as a crash would");
  fov::add_gaze_flags(*run, r.gaze);  // default: the fixation target
  run->add_flag("--gaze-mouse", r.gaze_mouse, "Gaze from the mouse pointer");
  run->add_option("--screen-ppd", r.screen_ppd,
                  "The screen's pixels per degree at the subject's distance: frames are scaled to keep the protocol display's "
                  "degrees (default: 1:1)");
  run->add_flag("--fullscreen", r.fullscreen, "A full-screen window, frames centred on black");
  run->add_option("--script-keys", r.script_keys, "Testing: the window's answers, one key per trial (e.g. nnyn)");

  CLI::App* sim = app.add_subcommand("simulate", "Estimate a procedure's bias, spread and trials with a simulated observer");
  sim->add_option("--protocol", so.protocol, "Protocol JSON")->required();
  sim->add_option("--observer", so.observer, "logistic:threshold=T,slope=S[,lapse=L][,false_alarm=F]")->required();
  sim->add_option("--runs", so.runs, "Simulated sessions (default 1000)");
  sim->add_flag("--json", so.json, "Print JSON");
  sim->add_option("--procedure", so.procedures, "Procedures to compare on the same observer: up-down, quest, quest-plus or all "
                  "(default: the protocol's)")->delimiter(',');
  sim->add_option("--step", so.overrides.step, "Override the rule's step");
  sim->add_option("--initial-step", so.overrides.initial_step, "Override the rule's initial step");
  sim->add_option("--start", so.overrides.start, "Override the starting scale (the top of the range descends)");
  sim->add_option("--thresholds", so.overrides.thresholds, "Override thresholds per series");
  sim->add_option("--discard", so.overrides.discard, "Override the reversals discarded");

  CLI::App* an = app.add_subcommand("analyze", "Thresholds, psychometric fits, means, ANOVA and plots from sessions");
  an->add_option("sessions", ao.inputs, "Session files (.jsonl)");
  an->add_option("--thresholds", ao.thresholds, "Instead: a CSV subject,condition,threshold (e.g. published data)");
  an->add_option("--out-csv", ao.out_csv, "Write every threshold as subject,condition,threshold");
  an->add_option("--plots", ao.plots, "Write staircase and psychometric plots into this directory (default: no plots)");
  an->add_option("--fit", ao.fits, "Psychometric functions fitted per subject and condition: weibull, logistic, normal, or none")
      ->delimiter(',');
  an->add_option("--bootstrap", ao.bootstrap, "Parametric bootstrap samples for each fit's threshold interval (0..10000)");
  an->add_flag("--json", ao.json, "Print JSON");

  fov::export_command_options eo;
  CLI::App* ex = app.add_subcommand("export", "Write sessions as PsychoPy-style CSV or BIDS behavioural files");
  ex->add_option("sessions", eo.inputs, "Session files (.jsonl)");
  ex->add_option("--format", eo.format, "psychopy (one CSV per session) or bids (_beh.tsv and .json per session)");
  ex->add_option("--out", eo.out_dir, "Directory to write into (created)")->required();
  ex->add_option("--task", eo.task, "BIDS task label, letters and digits (default foveation)");

  CLI::App* validate = app.add_subcommand("validate", "Check a protocol file and list the point sets it needs");
  validate->add_option("protocol", protocol, "Protocol JSON")->required();

  return fov::run_tool("fovstair", app, argc, argv, [&]() -> int {
    if (*run) return fov::run_session(r);
    if (*sim) return fov::simulate(so);
    if (*an) return fov::analyze(ao);
    if (*ex) return fov::export_command(eo);
    return fov::validate_protocol(protocol);
  });
}
