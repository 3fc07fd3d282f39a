// Every error measure of one frame against a reference, as the tools print and write it:
// fovrender --compare, fovbench compare and its sweep, and (PSNR/SSIM only) fovview's
// screenshots. One JSON schema for a comparison (comparison_json), written by every tool.
#pragma once

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "fov/flip.h"
#include "fov/fvvdp.h"
#include "fov/metrics.h"
#include "fov/renderer.h"

namespace fov {

// The one spelling of "no error" in JSON: a PSNR of identical images is +inf, written
// null (JSON has no infinity); CSV files write inf.
inline nlohmann::json db_json(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// What a comparison computes beyond PSNR/SSIM, and the display's light for JOD.
struct comparison_params {
  bool flip = true;               // FLIP and the foveated FLIP
  bool jod = true;                // FovVideoVDP: JOD foveated at the gaze and non-foveated
  bool keep_maps = false;         // FLIP's two maps
  display_photometry photometry;  // fvvdp.h; the default is the validation set's display
};

struct comparison {
  error_report error;  // PSNR/SSIM by band, foveated RMSE (metrics.h)
  flip_report flip;    // FLIP and the foveated FLIP (flip.h), when asked
  bool has_flip = false;
  fvvdp_result jod;    // FovVideoVDP (fvvdp.h), when asked and the frame is 8x8 pixels or more
  bool has_jod = false;
  std::vector<double> geometry;  // per band, the share of the reference's pixels on geometry (NaN: no depth)
};

// Bands of the report: 5, 10, 20, 30 degrees.
comparison compare_images(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                          const comparison_params& p = {});

// The JSON object of a comparison (docs/metrics.md lists the keys).
nlohmann::json comparison_json(const comparison& c);

// Lines for people: JOD, PSNR/SSIM by band, then FLIP, for a reference called `against`.
std::string comparison_text(const comparison& c, const std::string& against);

// A frame against a converged reference traced here (p with `spp` Sobol rays per pixel,
// seed converged_seeds(p.seed).first), and that reference's noise floor: a second one
// (the other seed) compared with it the same way. fovrender --reference-spp.
struct converged_comparison {
  comparison against, floor;
  double reference_ms = 0;  // tracing one of the two references
};
converged_comparison compare_converged(renderer& r, const frame& image, const spacing_model& eye, gaze_point gaze,
                                       const render_params& p, uint32_t spp, const comparison_params& what);

}  // namespace fov
