// Every error measure of one frame against a reference, as the tools print and write it:
// fovrender --compare, fovbench compare and (PSNR/SSIM only) fovview's screenshots.
#pragma once

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "fov/flip.h"
#include "fov/metrics.h"
#include "fov/renderer.h"

namespace fov {

// The one spelling of "no error" in JSON: a PSNR of identical images is +inf, written
// null (JSON has no infinity); CSV files write inf.
inline nlohmann::json db_json(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

struct comparison {
  error_report error;  // PSNR/SSIM by band, foveated RMSE (metrics.h)
  flip_report flip;    // FLIP and the foveated FLIP (flip.h), when asked
  bool has_flip = false;
  std::vector<double> geometry;  // per band, the share of the reference's pixels on geometry (NaN: no depth)
};

// Bands of the report: 5, 10, 20, 30 degrees.
comparison compare_images(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                          bool flip, bool keep_maps = false);

// The JSON object of a comparison (docs/metrics.md lists the keys).
nlohmann::json comparison_json(const comparison& c);

// Two lines for people: PSNR/SSIM by band, then FLIP, for a reference called `against`.
std::string comparison_text(const comparison& c, const std::string& against);

// A frame against a converged reference traced here (p with `spp` Sobol rays per pixel,
// seed converged_seeds(p.seed).first), and that reference's noise floor: a second one
// (the other seed) compared with it the same way. fovrender --reference-spp.
struct converged_comparison {
  comparison against, floor;
  double reference_ms = 0;  // tracing one of the two references
};
converged_comparison compare_converged(renderer& r, const frame& image, const spacing_model& eye, gaze_point gaze,
                                       const render_params& p, uint32_t spp, bool flip, bool keep_maps);

// `fovbench compare`: two image files, the display they are seen on and the gaze.
struct compare_options {
  std::string test, reference;
  std::string display;             // a preset or WxH, 8..8192 (parse_display; empty: the images' size)
  double viewing_distance = 0;     // display widths (0: the display's, 1 for WxH)
  std::string gaze = "centre";
  bool json = false, flip = true;
  std::string flip_map, foveated_flip_map;
};
// Reads both, checks sizes (usage_error for flags, file_error for files), compares and
// writes the maps; returns what to print (JSON or the two lines).
std::string run_compare(const compare_options& o);

// An error map as a grey image: byte = round(255 x error). Written as write_frame does.
void write_error_map(const error_map& map, const std::string& path);

}  // namespace fov
