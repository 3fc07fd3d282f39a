// Image error by eccentricity: how far a reconstructed frame is from the reference.
#pragma once

#include <cstdint>
#include <vector>

#include "fov/acuity.h"
#include "fov/frame.h"

namespace fov {

struct band_metrics {
  double psnr = 0;   // dB over RGB; +inf when identical
  double ssim = 0;   // mean SSIM over the band's pixels and channels
  uint64_t pixels = 0;
};

// How much a pixel's error matters at an eccentricity: the acuity model's cut-off
// frequency there relative to the display's Nyquist frequency, min(fc(e), fd) / fd in
// (0, 1]: 1 where the eye resolves every pixel, falling with eccentricity. Evaluated at
// the eye's true eccentricity (the model's scale is ignored: it thins sets, not eyes).
double acuity_weight(const spacing_model& eye, double eccentricity_deg);

// Everything measured of one frame against its reference, on display values: both are
// tone-mapped the way PNGs are written (clamped to [0, 1], sRGB-encoded, 8 bits), so
// errors are measured on what is displayed (below in units of full scale, 0..1). SSIM is
// OpenCV's (quality module, 11x11 Gaussian window), averaged over each band's pixels.
struct error_report {
  band_metrics overall;
  std::vector<double> edges_deg;    // band edges, e.g. 5, 10, 20, 30
  std::vector<band_metrics> bands;  // edges_deg.size() + 1 bands: [0, e0), [e0, e1), ..., [e_last, inf)
  // sqrt(sum_p w(e_p) err_p^2 / sum_p w(e_p)), err_p^2 the pixel's squared error averaged
  // over RGB, w = acuity_weight: an RMSE in which each pixel counts as much as the eye
  // can see of it. foveated_psnr = 20 log10(1 / foveated_error).
  double foveated_error = 0, foveated_psnr = 0;
  double bin_deg = 2.5;                // error profile: RMSE per eccentricity bin
  std::vector<double> profile_rmse;    // bin i covers [i bin_deg, (i + 1) bin_deg)
  std::vector<uint64_t> profile_pixels;
};
error_report measure_error(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                           const std::vector<double>& edges_deg = {5, 10, 20, 30}, double bin_deg = 2.5);

// Per band (edges as in error_report), the share of a frame's pixels whose rays hit
// geometry (finite depth): where a scene is sky, its errors say nothing. NaN for a band
// without pixels, and for every band of a frame without depth.
std::vector<double> geometry_coverage(const frame& f, const display_geometry& display, gaze_point gaze,
                                      const std::vector<double>& edges_deg = {5, 10, 20, 30});

// Mean absolute change of display luminance (Rec. 709 weights on sRGB-encoded values,
// 0..1) between two frames of the same size: the flicker measure.
double mean_luminance_change(const frame& a, const frame& b);

}  // namespace fov
