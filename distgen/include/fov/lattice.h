// Ring lattices: the deterministic samplers of the peers (fovgen --sampler polar|log-polar;
// docs/schemes.md). Both place a point at the canvas centre and rings of points around it,
// from the acuity model's sample pitch, on the same canvas and in the same file as darts.
#pragma once

#include <vector>

#include "fov/pointset.h"

namespace fov {

// The sample pitch at distance d from the canvas centre: q(d) = fd / min(fd, fc(e(d)))
// pixels (Eqs. 1-3), one sample per half cycle of the cut-off, 1 px where the display limits.
// Eq. 4 is q - (1 - sqrt(1/pi)): a dart's minimum distance, where a lattice keeps the pitch.
double lattice_pitch_px(const spacing_model& model, double distance_px);

// The rings' radii in pixels, increasing, from the first ring out to the first one past the
// canvas corner (the centre point is not a ring):
// - polar (HVVR): r1 = q(0), then r_{j+1} = r_j + q(r_j), the next ring a pitch out;
// - log_polar (VaFR): r_j where u(r_j) = j, u(r) = the integral of dr / q from 0 to r
//   (VaFR's Eq. 5 for any acuity model, evaluated numerically).
std::vector<double> lattice_rings(const spacing_model& model, point_sampler sampler);

// The samples on a ring of radius r, the same number for both lattices: ceil(2 pi r / q(r)).
// polar places them at angles (i + 1/2) 2 pi / n (HVVR's phase); log_polar at angles i q / r
// (VaFR's Eq. 9, its tangential pitch equal to the radial: the integers i below l = 2 pi r / q,
// the last gap shorter).
uint32_t lattice_ring_count(const spacing_model& model, double radius_px);

// The lattice's points on the canvas: the centre, then every ring's, each with its pitch as its
// spacing, in Morton order. sampler must not be poisson.
std::vector<point> lattice_points(const spacing_model& model, point_sampler sampler);

}  // namespace fov
