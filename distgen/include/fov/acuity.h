// Perceptual spacing model: how far apart the points of a foveated point set
// may lie at each distance from the gaze (thesis Sec. 4.1, Eqs. 1-4).
#pragma once

#include <cstdint>
#include <string>
#include <utility>

#include "fov/display.h"

namespace fov {

// Which acuity model turns eccentricity into a cut-off frequency (docs/schemes.md gives
// each one's equation, constants and source). A new model adds an enumerator, its label,
// its parameters to acuity_params and a case in cutoff_frequency_cpd() and validate(). The
// value is stored in point-set files, so never renumber.
enum class acuity_model : uint32_t {
  wang_csf = 1,       // the thesis: Wang et al. / Geisler & Perry contrast-sensitivity cut-off (Eq. 2)
  linear_mar = 2,     // Guenter et al. 2012 as HVVR samples it: a sample every MAR, w = m e + w0
  piecewise_mar = 3,  // VaFR Sec. 3.3: acuity given at 0, 10, 20, 30 and 60 degrees, MAR linear between
};
inline constexpr std::pair<const char*, acuity_model> acuity_model_labels[] = {
    {"csf", acuity_model::wang_csf}, {"linear-mar", acuity_model::linear_mar}, {"piecewise-mar", acuity_model::piecewise_mar}};

// The model's label ("csf", "linear-mar", "piecewise-mar"; "unknown" for any other value).
const char* acuity_model_name(acuity_model model);

// piecewise_mar: the eccentricities (degrees) at which its acuities are given (VaFR Eq. 12's
// segment ends); past the last the last segment's line goes on.
inline constexpr double piecewise_pivots_deg[5] = {0, 10, 20, 30, 60};

// The parameters' documented ranges (validate() refuses values outside them).
inline constexpr double max_mar_slope = 1.0;                            // linear_mar m: (0, 1]
inline constexpr double min_mar_fovea_deg = 1.0 / 600, max_mar_fovea_deg = 1.0;  // w0, degrees
inline constexpr double max_mar_dead_zone_deg = 30;                    // [0, 30] degrees
inline constexpr double min_pivot_cpd = 0.1, max_pivot_cpd = 200;      // piecewise acuities, cpd

// Parameters of every acuity model; each model reads only its own fields (the others keep
// their defaults, and files store only the model's own).
struct acuity_params {
  acuity_model model = acuity_model::wang_csf;
  // wang_csf (thesis Sec. 4.1)
  double ct0 = 1.0 / 64.0;  // minimum contrast threshold
  double alpha = 0.106;     // spatial-frequency decay constant
  double e2 = 2.3;          // half-resolution eccentricity, degrees
  // linear_mar: the minimum angle of resolution w(e) = m max(e - dead_zone, 0) + w0 degrees,
  // one sample per MAR, so fc = 1 / (2 w). Defaults: HVVR's (m = Guenter's conservative m_B).
  double mar_slope = 0.022;           // m, degrees of MAR per degree of eccentricity
  double mar_fovea_deg = 1.0 / 60.0;  // w0, degrees (20/20 acuity)
  double mar_dead_zone_deg = 0.5;     // eye-tracking uncertainty held at w0 (HVVR's 0.5 degrees)
  // piecewise_mar: the acuity f (cycles per degree, one cycle two samples) at each of
  // piecewise_pivots_deg; VaFR's MAR 1/f is linear in e between them, and fc = f.
  double pivot_cpd[5] = {40, 10, 6, 5, 4};
};

// Only the model's own parameters compared (the others do not change its spacing).
bool same_acuity(const acuity_params& a, const acuity_params& b);

// The model's label, followed by its parameters where they differ from the defaults, as
// file names use it: "csf", "linear-mar", "linear-mar-m0.0275-w0.02083-d0",
// "piecewise-mar-f40-12-6-5-4".
std::string acuity_label(const acuity_params& acuity);

// Everything that fixes the minimum point spacing at a given distance from the gaze.
struct spacing_model {
  display_geometry display;
  double scale = 1.0;  // s: eccentricity multiplier, thins the set (thesis 1.0 .. 3.0)
  acuity_params acuity;
};

// Eq. 1 with the thesis's scale: e = s * atan(d / (N v)), in degrees.
double eccentricity_deg(const spacing_model& model, double distance_px);

// The cut-off frequency in cycles per degree at eccentricity e (degrees). wang_csf: Eq. 2,
// fc = e2 ln(1/CT0) / ((e + e2) alpha); linear_mar: fc = 1 / (2 (m max(e - d, 0) + w0));
// piecewise_mar: fc = 1 / w(e), w linear between the pivots' 1/f.
double cutoff_frequency_cpd(const acuity_params& acuity, double eccentricity_deg);

// Eq. 3: fd = pi N v / 360, the display's Nyquist frequency in cycles per degree.
double display_nyquist_cpd(const display_geometry& display);

// Eq. 4: p = fd / min(fd, fc) - (1 - a), a = sqrt(1/pi). The minimum distance in
// pixels between a dart at this distance from the gaze and any accepted point.
// Non-decreasing in distance_px for every model (dart throwing relies on it).
double point_spacing_px(const spacing_model& model, double distance_px);

// Checks the model's numbers; returns an empty string when valid, else the reason.
std::string validate(const spacing_model& model);

}  // namespace fov
