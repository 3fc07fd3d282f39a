// The render flags every tool binds the same way, straight into fov::render_params.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "fov/renderer.h"

namespace fov {

// The groups of render flags; each tool binds the groups it takes. Ranges are checked by
// CLI11 (one line, exit 2); what depends on the point set (k) by fov::validate.
enum render_flags : unsigned {
  flags_spp = 1,           // --spp
  flags_trace = 2,         // --seed, --no-shadows, --texture-footprint, --exposure, --sun-dir, --sun-irradiance, --disc-sampler, --reference-sampler
  flags_method = 4,        // --method, --k
  flags_reconstruct = 8,   // --renka, --rbf-kernel, --rbf-shape
  flags_pattern = 16,      // --pattern
  flags_device = 32,       // --device
  flags_view = 64,         // --hfov, --eye, --look-at, --up, --camera
  flags_all = 127,
};
void add_render_flags(CLI::App& app, render_params& p, unsigned groups = flags_all);

// One line naming the flag when `p` is not valid (for `set`'s k when given): a usage_error.
void require_valid(const render_params& p, const pointset* set = nullptr);

}  // namespace fov
