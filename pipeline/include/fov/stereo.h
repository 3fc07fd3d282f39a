// Two eyes (issue 28): a head-mounted display shows each eye its own image (the FOVE 0 shows
// each a 1280x1440 half of its 2560x1440 panel), each eye with its own gaze. Both eyes use
// the same point set, each shifted to its own gaze, and cameras half the interpupillary
// distance to either side of the head's, looking the same way (parallel axes and symmetric
// frusta: the head camera's field of view for each eye). Most of what one eye sees the other
// sees too: with --reuse eyes the left eye is traced, and each point of the right eye keeps
// the left eye's sample that its centre sees, where temporal reuse's confidence (fov/reuse.h)
// holds, with the left eye's frame as the last frame (docs/reuse.md).
#pragma once

#include <cstdint>
#include <string>
#include <utility>

#include "fov/camera.h"
#include "fov/frame.h"
#include "fov/pointset.h"
#include "fov/reuse.h"

namespace fov {

enum class eye_side : uint8_t { left, right };
inline constexpr std::pair<const char*, eye_side> eye_side_labels[] = {{"left", eye_side::left}, {"right", eye_side::right}};

// The documented range of an interpupillary distance, millimetres: 0 (both eyes at the head's
// camera) to a metre (hyperstereo, or a world modelled in units smaller than metres).
constexpr double max_ipd_mm = 1000;

struct stereo_params {
  bool enabled = false;  // two eyes (--stereo)
  // The interpupillary distance in millimetres of a world measured in metres (glTF's unit and
  // the built-in scenes'): each eye sits half of it to its side of the head camera. 63 mm is
  // about the adult mean (Dodgson 2004).
  double ipd_mm = 63;
};
// "" when valid, else the reason naming the flag (--ipd).
std::string validate(const stereo_params& p);

// One eye's camera for a head at `head`: moved ipd_mm / 2000 world units along the head's
// right (left eye: to the left), looking the same way with the same field of view and up.
camera eye_camera(const camera& head, eye_side e, double ipd_mm);

// The samples another view traced of `set` from `cam` as a history trace_reusing reads (what
// --reuse eyes keeps from the left eye): each traced point seen where its centre's ray meets
// the mean depth of its rays (all its rays hit), in its centre's direction (all missed), or
// mixed (some hit: an edge, never kept). Built without probe rays: a disc's mean depth stands
// for its centre's (a disc across a depth edge lands between the surfaces, off both, and the
// reprojection term turns it down). Every sample's age is 0. `spp` is the rays each traced
// point cast (a ray floor's varying counts are refused by trace_reusing already).
reuse_history history_of(const point_samples& samples, const camera& cam, const pointset& set, uint32_t spp);

// The eyes' frames side by side (left | right), as a head-mounted display's panel shows
// them; both the same size.
frame side_by_side(const frame& left, const frame& right);
// One eye's half of a side-by-side frame (its width even).
frame eye_half(const frame& both, eye_side e);

}  // namespace fov
