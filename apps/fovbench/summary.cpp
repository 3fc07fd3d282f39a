#include "summary.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <tuple>

#include <fmt/format.h>

#include "../common/cli.h"
#include "../common/plot.h"
#include "fov/usage_error.h"
#include "fov/files.h"

namespace fov {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> results_files(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& input : inputs) {
    std::error_code ec;
    const fs::file_status st = fs::status(input, ec);
    if (ec || !fs::exists(st)) throw usage_error(fmt::format("summary: {}: no such file or directory", input));
    if (!fs::is_directory(st)) {
      files.push_back(input);
      continue;
    }
    std::vector<std::string> found;
    for (auto it = fs::recursive_directory_iterator(input, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      if (it->path().filename() == "results.csv" && it->is_regular_file(ec)) found.push_back(it->path().string());
      if (found.size() + files.size() > max_summary_files) break;
    }
    if (ec) throw usage_error(fmt::format("summary: {}: {}", input, ec.message()));
    if (found.empty()) throw usage_error(fmt::format("summary: {}: holds no results.csv", input));
    std::sort(found.begin(), found.end());
    files.insert(files.end(), found.begin(), found.end());
  }
  if (files.size() > max_summary_files)
    throw usage_error(fmt::format("summary: more than {} results.csv files; summarise fewer", max_summary_files));
  return files;
}

// What an answer is about, and the part of it every run must agree on.
using answer_key = std::tuple<std::string, std::string, std::string, std::string, std::string, scheme>;
answer_key key_of(const scheme_answer& a) { return {a.scene, a.taa_frames, a.taa_pattern, a.integrator, a.display, a.scheme}; }

std::string summary_csv(const std::vector<scheme_answer>& answers) {
  std::string csv =
      "scene,taa_frames,taa_pattern,integrator,display,ppd,pixels,noise_floor_jod,target_jod,yardstick_spp,yardstick_jod,yardstick_ms,"
      "yardstick_rays,scheme,reached,best,best_jod,best_ms,best_rays,best_points,speedup,speedup_lo,speedup_hi,goal,source\n";
  auto num = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{:g}", v); };
  for (const scheme_answer& a : answers)
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", csv_cell(a.scene), a.taa_frames,
                       a.taa_pattern, csv_cell(a.integrator), csv_cell(a.display), num(a.ppd), num(a.pixels), num(a.noise_floor_jod), num(a.target_jod),
                       num(a.yardstick_spp), num(a.yardstick_jod), num(a.yardstick_ms), num(a.yardstick_rays), label_of(scheme_labels, a.scheme),
                       a.reached ? 1 : 0, csv_cell(a.best), num(a.best_jod), num(a.best_ms), num(a.best_rays), num(a.best_points),
                       num(a.speedup.estimate), num(a.speedup.lo), num(a.speedup.hi), num(goal_speedup(a.ppd)), csv_cell(a.source));
  return csv;
}

// One panel per scene and integrator: per scheme, single frames (solid) and each steady state (dashed), the
// speedup where it reaches the yardstick (with the goal), or its best JOD against the
// yardstick's (every answer), against pixels per degree.
std::vector<plot_panel> panels(const std::vector<scheme_answer>& answers, bool speedup) {
  std::vector<std::pair<std::string, std::string>> scenes;  // scene, integrator
  for (const scheme_answer& a : answers)
    if (std::find(scenes.begin(), scenes.end(), std::make_pair(a.scene, a.integrator)) == scenes.end())
      scenes.emplace_back(a.scene, a.integrator);
  std::vector<plot_panel> out;
  for (const auto& [scene, traced] : scenes) {
    plot_panel p;
    p.title = short_scene(scene) + (traced == "direct" ? "" : " (" + traced + ")");
    p.x_label = "pixels per degree at the display's centre";
    p.y_label = speedup ? "speedup at the yardstick's JOD\n(95 % interval; log scale)" : "best JOD minus the yardstick's\n(>= 0: reaches it)";
    p.log_y = speedup;
    std::vector<const scheme_answer*> mine;
    for (const scheme_answer& a : answers)
      if (a.scene == scene && a.integrator == traced) mine.push_back(&a);
    std::stable_sort(mine.begin(), mine.end(), [](const scheme_answer* a, const scheme_answer* b) { return a->ppd < b->ppd; });
    std::vector<std::pair<std::string, std::string>> steady;  // single frames first, then each steady state
    for (const scheme_answer* a : mine)
      if (std::find(steady.begin(), steady.end(), std::make_pair(a->taa_frames, a->taa_pattern)) == steady.end())
        steady.emplace_back(a->taa_frames, a->taa_pattern);
    std::stable_sort(steady.begin(), steady.end(), [](const auto& a, const auto& b) { return a.first.empty() && !b.first.empty(); });
    bool any = false;
    for (const auto& [frames, pattern] : steady)
      for (const auto& [name, which] : scheme_labels) {
        plot_series s;
        s.name = frames.empty() ? std::string(name) : fmt::format("{}, TAA {} {}", name, frames, pattern);
        s.scheme = name, s.style = frames.empty() ? "solid" : "dashed";
        for (const scheme_answer* a : mine) {
          if (a->scheme != which || a->taa_frames != frames || a->taa_pattern != pattern || (speedup && !a->reached)) continue;
          s.x.push_back(a->ppd);
          if (speedup) s.y.push_back(a->speedup.estimate), s.y_lo.push_back(a->speedup.lo), s.y_hi.push_back(a->speedup.hi);
          else s.y.push_back(a->best_jod - a->yardstick_jod);
        }
        if (!s.x.empty()) p.series.push_back(s), any = true;
      }
    if (speedup && !any) p.title += " (no scheme reaches the yardstick)";
    std::vector<double> ppds;
    for (const scheme_answer* a : mine)
      if (ppds.empty() || ppds.back() != a->ppd) ppds.push_back(a->ppd);
    plot_series level;  // speed or quality equal to the yardstick's
    level.name = speedup ? "1x (the yardstick)" : "the yardstick", level.scheme = "full", level.style = "dotted", level.markers = false;
    level.x = {ppds.front(), ppds.back()}, level.y = {speedup ? 1.0 : 0.0, speedup ? 1.0 : 0.0};
    p.series.push_back(level);
    if (speedup) {
      plot_series goal;
      goal.name = "goal (issue 24)", goal.scheme = "goal", goal.lines = false;
      for (double ppd : ppds)
        if (!std::isnan(goal_speedup(ppd))) goal.x.push_back(ppd), goal.y.push_back(goal_speedup(ppd));
      if (!goal.x.empty()) p.series.push_back(goal);
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace

summary_result write_summary(const summary_options& s, int argc, char** argv) {
  if (s.inputs.empty()) throw usage_error("summary: give the results.csv (or directories holding them) to summarise");
  if (s.out.empty()) throw usage_error("summary: -o is required");
  if (!(s.target_jod > 0 && s.target_jod <= 10)) throw usage_error(fmt::format("--target-jod: {} is not in 0..10", s.target_jod));
  const fs::path md_path = fs::path(s.out) / "summary.md";
  if (fs::exists(md_path)) throw usage_error(fmt::format("-o {}: {} exists; summarise into a new directory", s.out, md_path.string()));
  require_output_dir("-o", s.out);
  summary_result result;
  result.files = results_files(s.inputs);
  std::vector<scheme_answer> by_level;
  // The full frame at each spp must score alike in every run of a scene and display.
  std::map<std::tuple<std::string, std::string, std::string, std::string, std::string, double>, const scheme_answer*> level_seen;
  for (const std::string& file : result.files) {
    const size_t before = by_level.size();
    for (scheme_answer& a : scheme_answers_by_level(read_results(file, true))) by_level.push_back(std::move(a));
    for (size_t i = before; i < by_level.size(); ++i) by_level[i].source = file;
  }
  for (const scheme_answer& a : by_level) {
    const auto [it, added] =
        level_seen.emplace(std::make_tuple(a.scene, a.taa_frames, a.taa_pattern, a.integrator, a.display, a.yardstick_spp), &a);
    if (!added && std::fabs(it->second->yardstick_jod - a.yardstick_jod) > 0.005)
      throw std::runtime_error(fmt::format("{}: full resolution at {} spp scores {:.3f} JOD, in {} {:.3f} (scene {}, display {}): "
                                           "not one study (other references or renders)",
                                           a.source, a.yardstick_spp, a.yardstick_jod, it->second->source, it->second->yardstick_jod,
                                           short_scene(a.scene), a.display));
  }
  std::map<answer_key, scheme_answer> best;
  std::vector<answer_key> order;
  for (const scheme_answer& a : at_goal(by_level, s.target_jod)) {
    const answer_key key = key_of(a);
    const auto it = best.find(key);
    if (it == best.end()) {
      order.push_back(key);
      best.emplace(key, a);
      continue;
    }
    scheme_answer& had = it->second;
    const bool better = a.reached ? !had.reached || a.speedup.estimate > had.speedup.estimate : !had.reached && a.best_jod > had.best_jod;
    if (better) had = a;
  }
  for (const answer_key& key : order) result.answers.push_back(best.at(key));
  if (result.answers.empty())
    throw std::runtime_error("summary: no run holds full-resolution rows with JOD beside a foveated scheme's; nothing to answer");

  std::string md = "# fovbench summary: one answer per display\n\n```\n";
  for (int i = 0; i < argc; ++i) md += (i ? " " : "") + std::string(argv[i]);
  md += fmt::format("\n```\n\n{} results.csv read; each cell is the best answer any of them gives (its file in summary.csv).\n\n",
                    result.files.size());
  md += scheme_answers_markdown(result.answers);
  md += "\nFigures: `speedup-vs-ppd` (each scheme's speedup where it reaches the yardstick's JOD, with the goal) and "
        "`jod-vs-ppd` (each scheme's best JOD against the yardstick's), PNG and SVG.\n";
  make_output_dir(s.out);
  const std::string csv = summary_csv(result.answers);
  write_file_atomic((fs::path(s.out) / "summary.csv").string(), csv.data(), csv.size());
  for (const bool speedup : {true, false}) {
    const std::string why = write_plot(panels(result.answers, speedup), (fs::path(s.out) / (speedup ? "speedup-vs-ppd" : "jod-vs-ppd")).string());
    if (!why.empty()) result.warnings.push_back(why);
  }
  write_file_atomic(md_path.string(), md.data(), md.size());
  return result;
}

}  // namespace fov
