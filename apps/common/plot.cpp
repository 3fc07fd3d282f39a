#include "plot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "fov/plot_script.h"
#include "fov/files.h"

extern char** environ;

namespace fov {

namespace fs = std::filesystem;

nlohmann::json figure_json(const std::vector<plot_panel>& panels, const std::vector<std::string>& outputs) {
  nlohmann::json j{{"outputs", outputs}, {"panels", nlohmann::json::array()}};
  for (const plot_panel& p : panels) {
    nlohmann::json panel{{"title", p.title}, {"x_label", p.x_label}, {"y_label", p.y_label}, {"log_x", p.log_x},
                         {"log_y", p.log_y}, {"series", nlohmann::json::array()}};
    for (const plot_series& s : p.series) {
      nlohmann::json out{{"name", s.name}, {"scheme", s.scheme}, {"style", s.style}, {"lines", s.lines}, {"markers", s.markers}};
      for (const char* key : {"x", "y", "x_lo", "x_hi", "y_lo", "y_hi", "labels", "ringed"}) out[key] = nlohmann::json::array();
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || (p.log_x && s.x[i] <= 0) || (p.log_y && s.y[i] <= 0)) continue;
        out["x"].push_back(s.x[i]), out["y"].push_back(s.y[i]);
        auto bar = [&](const std::vector<double>& v, const char* key, double fallback) {
          if (v.size() == s.x.size()) out[key].push_back(std::isfinite(v[i]) ? v[i] : fallback);
        };
        bar(s.x_lo, "x_lo", s.x[i]), bar(s.x_hi, "x_hi", s.x[i]), bar(s.y_lo, "y_lo", s.y[i]), bar(s.y_hi, "y_hi", s.y[i]);
        if (s.labels.size() == s.x.size()) out["labels"].push_back(s.labels[i]);
        if (s.ringed.size() == s.x.size()) out["ringed"].push_back(bool(s.ringed[i]));
      }
      panel["series"].push_back(out);
    }
    j["panels"].push_back(panel);
  }
  return j;
}

std::string write_plot(const std::vector<plot_panel>& panels, const std::string& stem) {
  const char* python = "/usr/bin/python3";
  if (access(python, X_OK) != 0) return fmt::format("{} is missing (scripts/install-deps.sh installs it)", python);
  std::error_code ec;
  const fs::path dir = fs::temp_directory_path(ec) / fmt::format("fovbench-plot-{}", getpid());
  fs::create_directories(dir, ec);
  if (ec) return fmt::format("cannot make {}: {}", dir.string(), ec.message());
  const std::string script = (dir / "plot.py").string(), data = (dir / "figure.json").string(), log = (dir / "stderr").string();
  const std::string text = figure_json(panels, {stem + ".png", stem + ".svg"}).dump();
  std::string why;
  try {
    write_file_atomic(script, plot_script::source, std::char_traits<char>::length(plot_script::source));
    write_file_atomic(data, text.data(), text.size());
  } catch (const std::exception& e) {
    why = e.what();
  }
  if (why.empty()) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    char* argv[] = {const_cast<char*>(python), const_cast<char*>(script.c_str()), const_cast<char*>(data.c_str()), nullptr};
    pid_t pid = 0;
    const int started = posix_spawn(&pid, python, &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    int status = 0;
    if (started != 0) {
      why = fmt::format("cannot run {}: {}", python, std::strerror(started));
    } else if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::ifstream in(log);
      std::string line, last;
      while (std::getline(in, line))
        if (!line.empty()) last = line;  // Python's error is its last line
      why = last.find("No module named 'matplotlib'") != std::string::npos
                ? "matplotlib is missing (scripts/install-deps.sh installs python3-matplotlib)"
                : fmt::format("{} failed: {}", python, last.empty() ? "no message" : last);
    }
  }
  fs::remove_all(dir, ec);
  return why.empty() ? "" : fmt::format("{}.png/.svg not drawn: {}", stem, why);
}

}  // namespace fov
