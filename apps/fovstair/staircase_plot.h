// A staircase series drawn as a PNG: scale per trial, answers, reversals, thresholds.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fov {

// `trials`: the series' trial records in order (catch trials are drawn as grey ticks).
// Written to a temporary file, then renamed.
void write_staircase_plot(const std::vector<nlohmann::json>& trials, const std::string& title, double scale_min,
                          double scale_max, const std::string& path);

}  // namespace fov
