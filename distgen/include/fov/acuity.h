// Perceptual spacing model: how far apart the points of a foveated point set
// may lie at each distance from the gaze (thesis Sec. 4.1, Eqs. 1-4).
#pragma once

#include <cstdint>
#include <string>

#include "fov/display.h"

namespace fov {

// Which acuity model turns eccentricity into a cut-off frequency. Only the
// thesis model exists; a new model adds an enumerator, its parameters to
// acuity_params and a case in cutoff_frequency_cpd(). The value is stored in
// point-set files, so never renumber.
enum class acuity_model : uint32_t {
  wang_csf = 1,  // Wang et al. / Geisler & Perry contrast-sensitivity cut-off
};

const char* acuity_model_name(acuity_model model);

// Parameters of every acuity model; each model reads only its own fields.
struct acuity_params {
  acuity_model model = acuity_model::wang_csf;
  double ct0 = 1.0 / 64.0;  // minimum contrast threshold
  double alpha = 0.106;     // spatial-frequency decay constant
  double e2 = 2.3;          // half-resolution eccentricity, degrees
};

// Everything that fixes the minimum point spacing at a given distance from the gaze.
struct spacing_model {
  display_geometry display;
  double scale = 1.0;  // s: eccentricity multiplier, thins the set (thesis 1.0 .. 3.0)
  acuity_params acuity;
};

// Eq. 1 with the thesis's scale: e = s * atan(d / (N v)), in degrees.
double eccentricity_deg(const spacing_model& model, double distance_px);

// Eq. 2 for wang_csf: fc = e2 ln(1/CT0) / ((e + e2) alpha), cycles per degree.
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
