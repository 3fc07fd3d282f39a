// Plots of sessions as PNGs: a staircase series (scale per trial, answers, reversals,
// thresholds), and a subject's psychometric data with the fitted functions.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis.h"

namespace fov {

// `trials`: the series' trial records in order (catch trials are drawn as grey ticks).
// Written to a temporary file, then renamed.
void write_staircase_plot(const std::vector<nlohmann::json>& trials, const std::string& title, double scale_min,
                          double scale_max, const std::string& path);

// The proportion detected (correct) at each scale, as discs of area proportional to the
// trials there, and each fitted function with its alpha and 95 % interval.
void write_psychometric_plot(const psychometric_data& data, const std::vector<psychometric_fit>& fits, const std::string& title,
                             double scale_min, double scale_max, const std::string& path);

}  // namespace fov
