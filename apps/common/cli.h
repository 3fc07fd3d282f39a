// What the command-line tools share: usage errors and gaze arguments.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "fov/acuity.h"

namespace fov {

// A usage problem: the tool prints one line and exits 2.
struct usage_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Parses the command line and runs `body`, turning every failure into the tools' policy:
// one line "TOOL: reason" on stderr; exit 2 for usage (bad flags), 1 for anything else.
int run_tool(const char* tool, CLI::App& app, int argc, char** argv, const std::function<int()>& body);

// "X,Y" in screen pixels, "centre"/"center" (W/2, H/2) or "corner" (W, H).
bool parse_gaze(const std::string& text, const display_geometry& display, double xy[2]);

// parse_gaze, or a usage_error naming `flag` when the text is malformed or off screen.
void require_gaze(const std::string& flag, const std::string& text, const display_geometry& display, double xy[2]);

}  // namespace fov
