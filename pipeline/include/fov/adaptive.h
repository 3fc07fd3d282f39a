// Per-frame refinement of a nested set (issue 26; docs/adaptive.md): trace the coarsest
// level, find where the contrast between its samples would be visible at that eccentricity
// under the acuity model, trace the next level there, and so on down to the finest, within a
// ray budget. The unit of refinement is a square block of canvas pixels: every pixel of a
// block reads one level's k nearest points, and all of them are traced.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fov/frame.h"
#include "fov/nested.h"
#include "fov/scene.h"
#include "fov/trace.h"

namespace fov {

// (refinement_block and refinement_map are in fov/frame.h, where the composite reads them.)

struct adaptive_params {
  bool enabled = false;
  // A block at level l is refined where the largest Michelson contrast between the samples it
  // reads, in any colour channel, reaches threshold x CT(f_l, e): the acuity model's contrast
  // threshold at the block's eccentricity e for the frequency f_l level l still resolves there
  // (docs/adaptive.md). 1 = the model's own limit; smaller refines more; 0 refines every block
  // to the finest level. 0..max_adaptive_threshold.
  double threshold = 1.0;
  // Also refined where the samples' depths differ by more than this fraction of the nearest,
  // or some hit and some miss (an edge of geometry); 0 = depth is not read.
  double depth_ratio = 0;
  // Rays per frame, the coarsest level's included; 0 = no limit. Refinements that would pass
  // it are left out, most visible first kept. The coarsest level is always traced whole.
  uint64_t budget = 0;
};
inline constexpr double max_adaptive_threshold = 1e3;
inline constexpr double max_depth_ratio = 1e3;
// "" when valid, else the reason naming the flag (--adaptive-threshold, ...).
std::string validate(const adaptive_params& p);

struct adaptive_report {
  std::vector<uint64_t> rays_per_level;    // rays cast for points first traced at each level
  std::vector<uint64_t> points_per_level;  // points first traced at each level
  std::vector<uint64_t> blocks_per_level;  // blocks that read each level
  uint64_t points_refined = 0;             // points traced beyond the coarsest level's
  uint64_t blocks_kept = 0;                // blocks that started from the previous frame's level
  uint64_t refinements_left_out = 0;       // visible refinements the budget had no room for
  bool budget_short = false;               // the coarsest level alone passed the budget
};

struct adaptive_trace {
  points_trace traced;  // indexed like the nested set (its finest level)
  refinement_map map;
  adaptive_report report;
};

// One refined frame of `levels` (make_levels of a nested set) at the gaze: tp as trace_points
// takes it (its seed, pattern and k); `previous`, when given and made for the same placement,
// is where the view did not change: its blocks start at their previous level. A point is
// traced exactly as trace_points traces it in the finest level's set, so a map that reads the
// finest level everywhere gives that set's frame.
adaptive_trace trace_adaptive(const scene& s, const camera& cam, const nested_levels& levels, gaze_point gaze,
                              const trace_params& tp, const adaptive_params& p, const refinement_map* previous = nullptr);

// Level l's samples (indexed like levels.levels[l].set) from a refined frame's.
point_samples level_samples(const nested_levels& levels, uint32_t l, const point_samples& all);

// The contrast threshold CT(f, e) of the set's acuity model (thesis Eq. 2 solved for CT:
// CT0 exp(alpha f (e + e2) / e2)) for frequency f (cycles per degree) at eccentricity e.
double contrast_threshold(const acuity_params& a, double f_cpd, double eccentricity_deg);

}  // namespace fov
