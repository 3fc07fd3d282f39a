// The render flags every tool binds the same way, straight into fov::render_params.
#pragma once

#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "fov/renderer.h"

namespace fov {

// The groups of render flags; each tool binds the groups it takes. Ranges are checked by
// CLI11 (one line, exit 2); what depends on the point set (k) by fov::validate.
enum render_flags : unsigned {
  flags_spp = 1,           // --spp
  flags_trace = 2,         // --seed, --no-shadows, --integrator, --bounces, --env-light, --texture-footprint, --exposure, --sun-dir, --sun-irradiance, --disc-sampler, --reference-sampler
  flags_method = 4,        // --method, --k
  flags_reconstruct = 8,   // --renka, --rbf-kernel, --rbf-shape
  flags_pattern = 16,      // --pattern
  flags_device = 32,       // --device
  flags_view = 64,         // --hfov, --eye, --look-at, --up, --camera
  flags_adaptive = 128,    // --adaptive, --adaptive-threshold, --adaptive-depth, --adaptive-budget
  flags_all = 255,         // the groups above
  // --camera-time, --rolling, --frame-period (with flags_view): a frame at a time on the
  // --camera path, its lines each at their own time. Only for tools that render one frame
  // at a time they are given (fovrender); a viewer moves its camera itself.
  flags_rolling = 256,
  // --reuse, --reuse-fovea, --reuse-threshold, --reuse-max-age, --reuse-budget, --reuse-view, --reuse-edges,
  // --reuse-distance: reuse (fov/reuse.h),
  // for tools that render frames in sequence.
  flags_reuse = 512,
  // --stereo, --ipd: two eyes side by side (fov/stereo.h), each its own gaze (the tool's --gaze-right).
  flags_stereo = 1024,
};
void add_render_flags(CLI::App& app, render_params& p, unsigned groups = flags_all);

// The point set a tool renders from a loaded file: the set itself, or with `level` >= 0 that
// level of a nested set as a fixed set (--level); a usage_error naming --level and the file
// when the set has no such level.
std::shared_ptr<const pointset> select_level(std::shared_ptr<const pointset> set, int level, const std::string& file);

// An adaptive frame's report as JSON (fovrender, fovbench, fovview --json): the params, and
// per level its scale, rays, points and blocks.
nlohmann::json refinement_json(const frame_timing& t, const render_params& p, const nested_levels& levels);
// A reusing frame's report as JSON: points kept and traced, probe and traced rays, the share
// kept, and points and kept points per eccentricity band.
nlohmann::json reuse_json(const reuse_report& r);
// "warning: ..." when the frame's coarsest level alone passed the budget, else "".
std::string refinement_warning(const frame_timing& t, const render_params& p);

// One line naming the flag when `p` is not valid (for `set`'s k when given): a usage_error.
void require_valid(const render_params& p, const pointset* set = nullptr);

}  // namespace fov
