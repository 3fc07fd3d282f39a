// Image error by eccentricity: how far a reconstructed frame is from the reference.
#pragma once

#include "fov/acuity.h"
#include "fov/trace.h"

namespace fov {

struct band_metrics {
  double psnr = 0;   // dB over RGB; +inf when identical
  double ssim = 0;   // mean SSIM over the band's pixels and channels
  uint64_t pixels = 0;
};

// Bands of the thesis discussion: fovea < 5 deg, mid 5-30 deg, periphery > 30 deg.
struct frame_comparison {
  band_metrics overall, fovea, mid, periphery;
};

// Eccentricity (degrees) of screen pixel (x, y)'s centre seen with the gaze at (gx, gy):
// atan(d / (W v)) for a screen W pixels wide viewed from v widths (thesis Eq. 1, s = 1).
double pixel_eccentricity_deg(const display_geometry& display, double gaze_x, double gaze_y, int x, int y);

// Compares two frames of the same size. Both are tone-mapped the way PNGs are written
// (clamped to [0, 1], sRGB-encoded, 8 bits): errors are measured on what is displayed.
// SSIM is OpenCV's (quality module, 11x11 Gaussian window), averaged over each band.
frame_comparison compare_frames(const frame& test, const frame& reference, const display_geometry& display,
                                double gaze_x, double gaze_y);

}  // namespace fov
