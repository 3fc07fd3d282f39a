// Temporal reuse (issue 28): a point whose centre sees, this frame, what a sample traced in an
// earlier frame saw keeps that sample instead of casting its rays again, unless it lies
// near the gaze or an edge, or the sample is too old. Backward and checked: every point the
// frame needs casts one probe ray through its centre (fov::probe_points); the hit is projected
// into the last frame's view, and of the points there nearest to it the one whose stored
// sample lies nearest to the hit in the world is the candidate. Its confidence is the product
// of Time-Warped Foveated Rendering's eccentricity term, a contrast term after its contrast
// term, and a reprojection term (docs/reuse.md):
//   c = S((e - fovea) / (2 fovea)) x (1 - C) x max(0, 1 - |hit - sample| / r) [x max(0, 1 - turn / view_deg)]
// with S the smoothstep, e the point's eccentricity in degrees (3 x fovea: fully peripheral),
// C the Michelson contrast of the candidates' luminances and r the point's disc radius carried
// to the hit's depth (for misses, the angle between the directions against the disc's angular
// radius); with reuse_distance::screen, the pixels between the point and the sample projected
// into the new view against the point's spacing. A sample with c >= threshold is kept. Not kept either: a point near an edge now (a
// neighbour's probe meets a surface 10 % nearer or farther, or a hit beside a miss) or then (a
// candidate's rays saw more than its centre: some hit and some missed, or their mean depth lay
// over half a disc from the centre's). A still view so keeps each point's own sample.
#pragma once

#include <cstdint>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "fov/camera.h"
#include "fov/frame.h"
#include "fov/pointset.h"
#include "fov/scene.h"
#include "fov/trace.h"

namespace fov {

enum class reuse_mode : uint8_t {
  none,      // every point traced every frame (what fovray always did)
  temporal,  // samples kept across frames where they still hold
  eyes,      // with two eyes (fov/stereo.h): the right eye keeps the left eye's samples where they hold
};
// Which discs of the last frame count as edges that keep their neighbours from being kept.
enum class reuse_edges : uint8_t {
  strict,       // silhouettes (some rays hit, some missed) and slopes (all hit, their mean depth
                // over half a disc from the centre's: a step or a grazing surface)
  silhouettes,  // silhouettes only: a step the new view shows is still caught by its probes
};
inline constexpr std::pair<const char*, reuse_edges> reuse_edges_labels[] = {{"strict", reuse_edges::strict},
                                                                            {"silhouettes", reuse_edges::silhouettes}};
// How far a candidate sample lies from what the point's probe sees, against the point's disc.
enum class reuse_distance : uint8_t {
  world,   // in the world: |hit - sample| against the disc carried to the hit's depth on a plane
           // facing the camera (a surface seen at a grazing angle spreads its samples farther)
  screen,  // on the screen, as TWFR reprojects: the sample projected into the new view, its
           // pixel distance from the point against the point's spacing, and (a hit) its depth
           // there within 10 % of the probe's
};
inline constexpr std::pair<const char*, reuse_distance> reuse_distance_labels[] = {{"world", reuse_distance::world},
                                                                                  {"screen", reuse_distance::screen}};
inline constexpr std::pair<const char*, reuse_mode> reuse_mode_labels[] = {
    {"none", reuse_mode::none}, {"temporal", reuse_mode::temporal}, {"eyes", reuse_mode::eyes}};

// Documented ranges.
constexpr double max_reuse_fovea_deg = 60;
constexpr uint32_t max_reuse_age = 1000;
constexpr uint64_t max_reuse_budget = uint64_t(1) << 40;
constexpr double max_reuse_view_deg = 180;

struct reuse_params {
  reuse_mode mode = reuse_mode::none;
  // Points within this eccentricity (degrees) are always traced; confidence rises from 0
  // there to 1 at three times it (TWFR: 10 and 30 degrees; here 5, the thesis's foveal band).
  double fovea_deg = 5;
  double threshold = 0.2;  // the least confidence a reused sample needs (TWFR's epsilon), 0..1
  // The most frames in a row a sample may be reused: every point is traced again at least
  // every max_age + 1 frames (1..max_reuse_age).
  uint32_t max_age = 16;
  // The most rays a frame's traced points may cast (probes not counted; 0: no limit). Points
  // that find no sample within their disc (disocclusion, an edge, a sample past its age) are
  // traced whatever it says; of the rest below the threshold the least confident (then the
  // nearest the gaze) are traced while it lasts, and the others keep their sample
  // (0..max_reuse_budget).
  uint64_t budget = 0;
  // The most the direction from the eye to a kept sample's surface may have turned since it
  // was traced, in degrees (0: no limit, TWFR's rule): confidence falls linearly from 1 at no
  // turn to 0 at this. Shading that depends on the view (a glossy highlight) moves with it;
  // a second eye looks at a near surface from another direction (0..max_reuse_view_deg).
  double view_deg = 0;
  // What counts as an edge then (reuse_edges): a point whose candidates include one is traced.
  // With silhouettes, a sloped sample is a candidate as a hit is.
  reuse_edges edges = reuse_edges::strict;
  reuse_distance distance = reuse_distance::world;  // the reprojection term's distance
};
// "" when valid, else the reason naming the flag (--reuse-fovea, --reuse-threshold, --reuse-max-age,
// --reuse-budget, --reuse-view).
std::string validate(const reuse_params& p);

// What earlier frames left, per point of the set: its last sample, where in the world that
// sample was seen from its centre, and how many frames it has been reused.
struct reuse_history {
  // nothing: not traced last frame; mixed: its rays saw more than its centre did (some hit and
  // some missed), a silhouette; sloped: all hit but their mean depth lies over half a disc from
  // the centre's (a depth step within the disc, or a surface seen at a grazing angle).
  enum class seen : uint8_t { nothing, hit, miss, mixed, sloped };
  std::vector<glm::vec3> colour;
  std::vector<glm::vec3> where;  // world position (hit) or unit direction (miss)
  // A hit's mean depth over its rays less its centre's depth, as traced: a reused sample's
  // depth is its centre's depth in the new view plus this (a still view: its depth as traced).
  std::vector<float> depth_bias;
  std::vector<uint16_t> hits;
  std::vector<seen> kind;
  std::vector<uint16_t> age;
  camera_frame view;  // the last frame's camera
  canvas_offset offset;
  bool mirror_x = false, mirror_y = false;
  bool valid = false;
  // What deciding reads of one point, gathered once a frame into one record (trace_reusing).
  struct record {
    glm::vec3 at{0};  // its sample: world position or direction, or (screen distance) its screen position and depth here
    float luminance = 0;
    float seen_now = 0;  // this frame's probe distance (+inf: a miss; NaN: not probed)
    uint16_t age = 0;
    seen kind = seen::nothing;
  };
  // The arrays of the history before this one, for the next frame to write over instead of
  // allocating its own (trace_reusing), and the records deciding gathers. Not part of the
  // history's value: a copy starts without them.
  struct arrays {
    std::vector<record> records;  // (scratch for deciding)
    std::vector<glm::vec3> colour, where;
    std::vector<float> depth_bias;
    std::vector<uint16_t> hits;
    std::vector<seen> kind;
    std::vector<uint16_t> age;
    arrays() = default;
    arrays(const arrays&) {}
    arrays& operator=(const arrays&) { return *this; }
    arrays(arrays&&) = default;
    arrays& operator=(arrays&&) = default;
    ~arrays() = default;
  } spare;
  void clear() { *this = reuse_history{}; }
  // n points, none seen (its view and placement left as they are; not valid).
  void reset(size_t n);
};

// The eccentricity bands a reuse report counts in: below 5, 5-10, 10-15, 15-30 and above 30 degrees.
inline constexpr double reuse_band_edges_deg[] = {5, 10, 15, 30};
constexpr size_t reuse_bands = 5;

// Why a point the frame needed was traced (or that it kept its sample), in the order the
// tests run: the first that holds.
enum class reuse_verdict : uint8_t {
  kept,
  no_history,       // the first frame, or the set changed
  eccentricity,     // too near the gaze: the eccentricity term alone is below the threshold
  off_canvas,       // its screen position falls off the set's canvas, or its probe's hit off (or
                    // behind) the last frame's view
  edge_now,         // a neighbour's probe met another surface (10 % off, or a hit beside a miss)
  edge_then,        // a candidate was an edge then (reuse_edges)
  no_candidate,     // no candidate saw what its probe sees (hit or miss, within age, [depth])
  out_of_reach,     // the nearest candidate lies a disc or more away: the reprojection term is 0
  below_threshold,  // the confidence is below the threshold (under a budget: and it was traced)
};
inline constexpr std::pair<const char*, reuse_verdict> reuse_verdict_labels[] = {
    {"kept", reuse_verdict::kept},
    {"no_history", reuse_verdict::no_history},
    {"eccentricity", reuse_verdict::eccentricity},
    {"off_canvas", reuse_verdict::off_canvas},
    {"edge_now", reuse_verdict::edge_now},
    {"edge_then", reuse_verdict::edge_then},
    {"no_candidate", reuse_verdict::no_candidate},
    {"out_of_reach", reuse_verdict::out_of_reach},
    {"below_threshold", reuse_verdict::below_threshold}};
constexpr size_t reuse_verdicts = std::size(reuse_verdict_labels);

// What a frame reused.
struct reuse_report {
  uint64_t points = 0;       // points the frame needed
  uint64_t reused = 0;       // of them, kept from the history
  uint64_t traced = 0;       // of them, traced
  uint64_t probe_rays = 0;   // one a point
  uint64_t rays_traced = 0;  // the traced points' rays (probes not included)
  uint64_t rays_reused = 0;  // the rays the reused points would have cast
  // Per eccentricity band (reuse_band_edges_deg; the viewer's eccentricity of each point's
  // screen position): the points the frame needed and those that kept a sample.
  uint64_t points_by_band[reuse_bands] = {}, reused_by_band[reuse_bands] = {};
  // Under a budget (reuse_params::budget): the points kept below the threshold because it ran
  // out (counted in `reused` too), and whether the points that had to be traced alone
  // passed it.
  uint64_t kept_for_budget = 0;
  bool budget_short = false;
  // The points by verdict (reuse_verdict; the budget's kept count as kept).
  uint64_t by_verdict[reuse_verdicts] = {};
  // Where the frame's wall time went, ms: probing every point, deciding which keep a sample,
  // tracing the rest, and keeping this frame's samples as the next frame's history.
  double ms_probe = 0, ms_decide = 0, ms_trace = 0, ms_history = 0;
  double reused_share() const { return points ? double(reused) / double(points) : 0.0; }
};

struct reused_trace {
  points_trace trace;  // samples of every point the frame needs; samples.rays and stats: traced rays and probes
  reuse_report report;
  std::vector<uint32_t> kept;  // the points that kept a sample, ascending
};

// One frame with temporal reuse: probes every point the frame needs (trace_points' list for
// this gaze), keeps the history's sample where its confidence reaches p.threshold, traces the
// rest, and leaves this frame's samples in `history` for the next. An invalid history (the
// first frame) reuses nothing. Every point is traced with trace_points' rays (params.ray_floor
// must be 0). Throws std::invalid_argument for invalid params.
reused_trace trace_reusing(const scene& s, const camera& cam, const pointset& set, const traced_index& index,
                           gaze_point gaze, const trace_params& params, const reuse_params& p, reuse_history& history);

}  // namespace fov
