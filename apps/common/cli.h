// What the command-line tools share: usage errors, gaze arguments, enum options.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

#include "fov/acuity.h"
#include "fov/labels.h"
#include "fov/usage_error.h"  // a usage problem: the tool prints one line and exits 2

namespace fov {


// For the tools that render frame after frame (fovrender, fovview, fovbench): every frame
// allocates and frees buffers of tens of MB, which glibc by default returns to the kernel
// (munmap, trim) for the next frame to page-fault back in, zeroed. Keeps them in the heap
// (docs/fovview.md); call first in main.
void keep_frame_buffers_in_heap();

// Parses the command line and runs `body`, turning every failure into the tools' policy:
// one line "TOOL: reason" on stderr; exit 2 for usage (bad flags), 1 for anything else.
int run_tool(const char* tool, CLI::App& app, int argc, char** argv, const std::function<int()>& body);

// "X,Y" in screen pixels, "centre"/"center" (W/2, H/2) or "corner" (W, H).
bool parse_gaze(const std::string& text, const display_geometry& display, gaze_point& out);

// A display spec (fov::parse_display: a preset, WxH, WxH@Nppd, WxH@Ndeg or WxH@V); a
// viewing distance other than 0 replaces the spec's (--viewing-distance). Throws a usage_error
// naming the flag. Every tool's --display goes through it.
display_geometry require_display(const std::string& flag, const std::string& text, double viewing_distance = 0);

// The help line of every --display flag.
std::string display_help();

// parse_gaze, or a usage_error naming `flag` when the text is malformed or off screen.
gaze_point require_gaze(const std::string& flag, const std::string& text, const display_geometry& display);

// Checks an output file before any work (fov::check_writable: not a directory, link,
// device or one of `inputs`; its directory writable); a usage_error naming `flag` if not.
// Empty paths (an output not asked for) pass.
void require_output(const std::string& flag, const std::string& path, const std::vector<std::string>& inputs = {});

// An output directory, checked before any work and without making it: a usage_error naming
// `flag` unless it (or, when missing, the nearest part of its path that exists) is a
// directory this process can write in.
void require_output_dir(const std::string& flag, const std::string& dir);

// An option whose values are an enum's labels (its label table): CLI11 maps the text to
// the value and rejects any other with one line; the choices (and, unless show_default
// is false, the default) appear in --help.
// Works for a vector of the enum too (a list option).
template <class T, class E, size_t N>
CLI::Option* add_label_option(CLI::App& app, const std::string& name, T& value, const label_table<E, N>& table,
                              const std::string& what, bool show_default = true) {
  CLI::Validator labels(
      [&table](std::string& text) -> std::string {
        E e{};
        if (!parse_label(table, text, e)) return "unknown '" + text + "' (" + label_list(table) + ")";
        text = std::to_string(static_cast<long long>(e));  // CLI11 converts the number to the enum
        return "";
      },
      "", "label");
  std::string help = what + ": " + label_list(table);
  if constexpr (std::is_same_v<T, E>)
    if (show_default) help += std::string(" (default ") + label_of(table, value) + ")";
  return app.add_option(name, value, help)->transform(labels);
}

}  // namespace fov
