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

// The samples on a ring of radius r: polar, ceil(2 pi r / q(r)) at angles (i + 1/2) 2 pi / n
// (HVVR's phase); log_polar, l = 2 pi r / q(r) (VaFR's Eq. 9 with its tangential pitch equal
// to the radial) at angles i 2 pi / l for the integers i < l (the last gap shorter).
uint32_t lattice_ring_count(const spacing_model& model, point_sampler sampler, double radius_px);

// The lattice's points on the canvas: the centre, then every ring's, each with its pitch as its
// spacing, in Morton order. sampler must not be poisson.
std::vector<point> lattice_points(const spacing_model& model, point_sampler sampler);

}  // namespace fov
