// Perceptual error: LDR-FLIP (Andersson et al., "FLIP: A Difference Evaluator for
// Alternating Images", HPG 2020), written from the paper's equations, and a foveated
// FLIP whose contrast-sensitivity and feature filters widen with eccentricity as the
// acuity model's cut-off frequency falls (docs/metrics.md).
#pragma once

#include <cstdint>
#include <vector>

#include "fov/acuity.h"
#include "fov/frame.h"

namespace fov {

// An error map: one value in [0, 1] per screen pixel, row-major.
struct error_map {
  int width = 0, height = 0;
  std::vector<float> value;
};

// Pixels per degree of visual angle at the display's centre: N v pi / 180 for a screen N
// pixels wide seen from v widths (twice the Nyquist frequency of thesis Eq. 3).
double display_ppd(const display_geometry& display);

// LDR-FLIP of `test` against `reference` (same size) seen at `ppd` pixels per degree.
// Both are taken as displayed: clamped to [0, 1], sRGB-encoded and quantised to 8 bits,
// as PNGs are written and as the PSNR of metrics.h sees them. Throws
// std::invalid_argument on frames of different sizes or ppd outside (0, 1000].
error_map flip_map(const frame& test, const frame& reference, double ppd);

// The pixels per degree at which the eye sees a pixel `eccentricity_deg` from the gaze,
// for the foveated FLIP: ppd fc(0) / fc(e), fc the acuity model's cut-off frequency. At
// e = 0 it is ppd; where the eye resolves half the frequency, detail twice as fine is
// filtered out, as if the image were seen from twice as far.
double foveated_ppd(double ppd, const acuity_params& acuity, double eccentricity_deg);

// Foveated FLIP: every pixel's value is FLIP at foveated_ppd of its eccentricity (the
// display's ppd at the gaze). Evaluated on a pyramid: levels at ppd 2^(j/2), level j on
// the images area-averaged by 2^floor(j/2) (what a more distant viewer's retina
// receives), maps interpolated between the two levels around each pixel's ppd. Equal to
// flip_map wherever foveated_ppd is the display's ppd (at the gaze). Levels stop where
// the image would fall below 8 pixels or at `max_levels`.
error_map foveated_flip_map(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                            int max_levels = 16);

// A map reduced to numbers, by eccentricity: mean over the screen, per band (edges as in
// error_report: [0, e0), [e0, e1), ..., [e_last, inf)), the worst band's mean, and a high
// percentile. Means over a whole frame hide a visible foveal error behind an invisible
// periphery; the worst band and the percentile do not.
struct pooled_error {
  double mean = 0;
  std::vector<double> edges_deg;
  std::vector<double> bands;       // mean per band; NaN for a band without pixels
  std::vector<uint64_t> pixels;    // per band
  double worst_band = 0;           // the largest band mean
  double p99 = 0;                  // 99th percentile of the map
};
pooled_error pool_error(const error_map& map, const display_geometry& display, gaze_point gaze,
                        const std::vector<double>& edges_deg = {5, 10, 20, 30});

// Both FLIPs of one frame against its reference (FLIP at the display's ppd), pooled;
// the maps themselves only when asked for.
struct flip_report {
  double ppd = 0;
  pooled_error flip, foveated;
  error_map flip_map, foveated_map;  // keep_maps
};
flip_report measure_flip(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                         const std::vector<double>& edges_deg = {5, 10, 20, 30}, bool keep_maps = false);

}  // namespace fov
