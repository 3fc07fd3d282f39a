// Detail the periphery can detect but not resolve, restored as noise (after Tariq et al.,
// SIGGRAPH 2022; issue 26's optional part, measured in docs/adaptive.md). A traced point's
// rays spread over its disc; their standard deviation (point_samples::spread) is the
// contrast inside the disc that scattered interpolation smooths away. This adds it back as
// per-pixel noise of that amplitude, interpolated like the colours, outside the fovea.
#pragma once

#include <cstdint>
#include <string>

#include "fov/display.h"
#include "fov/frame.h"

namespace fov {

struct detail_noise_params {
  float gain = 0;        // noise amplitude in units of the interpolated spread, 0..4; 0: off
  float from_deg = 5;    // eccentricity (degrees) where it starts, 0..90
  float ramp_deg = 5;    // and the degrees over which it grows to its full gain, 0..90
  bool enabled() const { return gain > 0; }
};

// "" when p is valid, else the reason naming the flag (--detail-noise, --detail-noise-from).
std::string validate(const detail_noise_params& p);

// The gain at eccentricity e (degrees): 0 below from_deg, rising linearly over ramp_deg to p.gain.
float detail_noise_gain(const detail_noise_params& p, double eccentricity_deg);

// Adds detail_noise_gain(p, e) x spread x n to every pixel of `image` (clamped at 0), where
// spread is `spread`'s pixel (the points' spreads reconstructed as a frame of the same size)
// and n one number per pixel of mean 0 and variance 1 (four uniforms summed: close to a
// normal one, within +-3.46), drawn from (seed, pixel): the same noise for the same seed,
// shared by the three channels. Throws std::invalid_argument when the sizes
// differ from each other or from the display's.
void add_detail_noise(frame& image, const frame& spread, const display_geometry& display, gaze_point gaze,
                      const detail_noise_params& p, uint64_t seed);

}  // namespace fov
