// Tracing: per-point colours for a foveated frame, and the full-resolution reference.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "fov/camera.h"
#include "fov/frame.h"
#include "fov/labels.h"
#include "fov/pointset.h"
#include "fov/scene.h"

namespace fov {

// Where tracing time goes, in thread-seconds summed over worker threads. Measured only
// when trace_params::time_stages is set: each stage costs two clock reads a packet.
struct trace_timing {
  double setup = 0;      // choosing points, generating rays
  double intersect = 0;  // rtcIntersect16 of primary rays
  double shade = 0;      // surface attributes, textures, environment
  double shadow = 0;     // rtcOccluded16 of shadow rays
  double bounce = 0;     // the path integrator's bounces: their rays, shading and shadow rays
  // Of `bounce`: the rtcIntersect1 and rtcOccluded1 calls of its rays (two clock reads a ray).
  double bounce_rays = 0;
  double total() const { return setup + intersect + shade + shadow + bounce; }
};

// How a ray's colour is found (docs/tracer.md, "Materials and integrators").
enum class integrator {
  direct,  // the scene's light at the first hit (a hard shadow) plus an ambient term: the
           // environment's mean colour times environment::ambient times the surface's albedo
           // (and occlusion texture); no bounce (default: what fovray always did)
  path,    // path tracing: the first hit and up to trace_params::bounces more, each vertex
           // lit by the lights through shadow rays (next-event estimation; the environment
           // image and emissive triangles too, with multiple importance sampling), the
           // environment and emissive surfaces also reached by BRDF-sampled bounces;
           // Russian roulette from the fourth bounce on; no ambient term
};
inline constexpr std::pair<const char*, integrator> integrator_labels[] = {{"direct", integrator::direct},
                                                                          {"path", integrator::path}};
// The most bounces a path may take (trace_params::bounces).
constexpr uint32_t max_bounces = 64;

// The filter width of a traced point's ray for texture and environment lookups.
enum class texture_footprint {
  disc,   // its share of the point's disc, radius p / sqrt(spp): the point's colour is
          // prefiltered over its whole disc, as the thesis asks (default)
  pixel,  // a full-resolution pixel's share, radius 0.5 / sqrt(spp): sharper and, where
          // textures are minified, cheaper (one MIP level), but peripheral points alias
};
// The one label table of the enum: names for the command lines, JSON and CSV files.
inline constexpr std::pair<const char*, texture_footprint> texture_footprint_labels[] = {
    {"disc", texture_footprint::disc}, {"pixel", texture_footprint::pixel}};
const char* texture_footprint_name(texture_footprint f);  // its label

// Where a full-resolution pixel's rays go inside it.
enum class pixel_sampler {
  sobol,   // the first spp points of a 2D Sobol (0,2)-sequence, Owen-scrambled per pixel and
           // seed: stratified at every power of two, so the mean converges far faster than
           // with independent positions; two seeds give independent estimates (default)
  random,  // independent uniform positions (what every reference used before)
};
inline constexpr std::pair<const char*, pixel_sampler> pixel_sampler_labels[] = {
    {"sobol", pixel_sampler::sobol}, {"random", pixel_sampler::random}};

// The most rays a point or pixel may cast (hit counts are 16-bit).
constexpr uint32_t max_spp = 65535;

// A foveated sampling rate on the full pixel grid (issue 24): every pixel is traced, its
// rays falling with eccentricity as the acuity model's point density falls, from
// trace_params::spp at the gaze to `floor`:
//   n(d) = clamp(round(spp * (p(0) / p(d))^2), floor, spp)
// where p is point_spacing_px of `model` (its display, acuity model and scale) at the pixel
// centre's distance d from the gaze. A pixel casts the first n of its full-resolution rays,
// so floor == spp (a flat rule) is the full-resolution frame, bit for bit.
struct ray_falloff {
  spacing_model model;
  gaze_point gaze;
  uint32_t floor = 1;  // 1..spp
};
// "" when the falloff can be traced at spp, else why not.
std::string falloff_problem(const ray_falloff& f, uint32_t spp);

// n(d) for every distance at once: thresholds[j] is the largest pixel distance from the gaze
// at which a pixel still casts floor + 1 + j rays (bisection on the model, within 1e-9 px).
struct falloff_rule {
  uint32_t floor = 1;
  std::vector<double> thresholds;  // spp - floor entries, non-increasing
  uint32_t rays_at(double distance_px) const;
};
falloff_rule make_falloff_rule(const ray_falloff& f, uint32_t spp);

// One camera per row (or column) of the screen (trace_params::lines). Every ray is cast from
// the camera of the line its screen position falls in (lines beyond the screen: the nearest
// one on it, for the off-screen points a reconstruction reads), so a ray's origin, direction
// and the depth it reports are its line's; the trace's camera argument is then not used.
struct line_cameras {
  bool columns = false;         // one camera per column, else per row
  std::vector<camera> cameras;  // the screen's height (rows) or width (columns) of them; empty: none
  bool empty() const { return cameras.empty(); }
};

struct trace_params {
  uint32_t spp = 32;     // rays per point (foveated) or per pixel (reference)
  uint64_t seed = 1;     // fixes the ray positions (and a path's bounces): the same every frame
  bool shadows = true;   // hard shadows from the scene's light
  integrator method = integrator::direct;
  uint32_t bounces = 2;  // path only: bounces after the first hit, 0..max_bounces
  // Path only: a lat-long environment image is also sampled as a light at every vertex (by
  // luminance, weighted against BRDF sampling by multiple importance sampling); off, it is
  // reached by BRDF-sampled bounces alone (a constant environment always is).
  bool sample_environment = true;
  // Path only: the scene's emissive triangles (opaque materials with an emissive factor) are
  // also sampled as lights at every vertex (by area times the factor's luminance, weighted
  // against BRDF sampling by multiple importance sampling); off, they light by BRDF-sampled
  // bounces alone. A scene without such triangles traces the same either way.
  bool sample_emitters = true;
  // The TAA pattern m = mirror_x + 2 mirror_y (thesis Sec. 3.3: four patterns from one set,
  // so TAA can blend frames with different samples). Foveated: the point set mirrored
  // left-right and/or top-bottom (a grid point casts its pixel's samples m n .. (m + 1) n - 1).
  // Full grid (trace_reference): every pixel casts its samples m n .. (m + 1) n - 1, as a grid
  // point there does; pattern 0 is the frame without a pattern.
  bool mirror_x = false, mirror_y = false;
  texture_footprint footprint = texture_footprint::disc;  // foveated only
  // Foveated only: the neighbours each pixel's reconstruction reads; it decides which
  // off-screen points must be traced too (traced_point_mask).
  uint32_t k = 5;
  bool time_stages = false;  // measure trace_stats::timing
  // Keep every ray the trace casts (trace_stats::recorded), for a bare Embree loop that casts
  // the same rays the same way (tracer_bench). Memory: 32 bytes a ray.
  bool record_rays = false;
  // Reference only: measure trace_stats::tile_seconds.
  bool tile_costs = false;
  // The positions of a full-resolution pixel's rays: the reference's, and a foveated grid
  // point's (fovgen --fovea grid), which casts its pixel's rays.
  pixel_sampler sampler = pixel_sampler::sobol;
  // Foveated only: the positions of a point's rays in its disc (random: the thesis's).
  pixel_sampler disc_sampler = pixel_sampler::random;
  // Every traced colour times 2^exposure_ev (a camera's exposure; -20..20). Displayed
  // values are then clamped to [0, 1] and sRGB-encoded (colour.h): no other tone curve.
  float exposure_ev = 0;
  // The light to shade with instead of the scene's (its direction, irradiance or position).
  std::optional<light> sun;
  // Reference only: rays per pixel fall with eccentricity (ray_falloff) instead of spp everywhere.
  std::optional<ray_falloff> falloff;
  // Foveated only: 0 = every point casts spp rays (the thesis); 1..spp = a point's rays fall
  // with eccentricity as the full grid's do (point_ray_rule), from spp at the gaze to this floor.
  uint32_t ray_floor = 0;
  // A camera per screen line instead of one for the frame: a rolling display's view, each
  // line seen from where the camera is when that line is shown (the pipeline's
  // rolling_params make them). Empty: every ray from the trace's camera.
  line_cameras lines;
};

// The rays of a foveated point (trace_params::ray_floor > 0): the falloff of the set's own
// model (display, acuity model, scale) at the frame's gaze, read at the distance d of the
// point's screen position from the gaze:
//   n(d) = clamp(round(spp * (p(0) / p(d))^2), floor, spp).
// A dart's own spacing is its model's p at its distance from the canvas centre (the gaze, up
// to its rounding to a whole pixel), so a rule of the point's footprint, spp (p(0) / p_i)^2,
// counts the same rays: one rule serves both. A
// grid point lies on its pixel's centre, so it casts the first n(d) of its pixel's rays, as
// that pixel does in the full grid's falloff frame (ray_falloff at the same model and gaze):
// a grid fovea with falling rays is the hybrid of issue 24 (the grid where the model's
// spacing is near a pixel, sparse points beyond). A point's n rays are the first n of its
// spp-ray stream, so its colour is what it gets in a flat trace at spp = n.
falloff_rule point_ray_rule(const pointset& set, gaze_point gaze, uint32_t spp, uint32_t floor);

// The rays a trace cast, by kind (always counted).
struct ray_counts {
  uint64_t primary = 0;  // from the camera, in packets of 16
  uint64_t shadow = 0;   // towards a light, a direction drawn from the environment light or an emissive triangle
  uint64_t bounce = 0;   // the path integrator's bounces, one at a time
  uint64_t total() const { return primary + shadow + bounce; }
};

// A ray as the tracer cast it (trace_params::record_rays).
struct recorded_ray {
  enum class kind : uint8_t {
    primary,        // rtcIntersect16, a packet of a task's consecutive primary rays
    packet_shadow,  // rtcOccluded16, the shadow rays of one packet's hits towards one light
    bounce,         // rtcIntersect1
    shadow,         // rtcOccluded1, a path vertex's shadow ray
  };
  glm::vec3 origin{0}, dir{0};
  float tfar = 0;
  kind how = kind::primary;
  bool starts_packet = false;  // the first ray of a packet (primary and packet_shadow)
};

// What a trace measured, when trace_params asked for it.
struct trace_stats {
  ray_counts cast;      // always
  trace_timing timing;  // time_stages
  // record_rays: each task's rays in the order it cast them, one list per task (the tracer's
  // split over threads; the lists' order is not deterministic).
  std::vector<std::vector<recorded_ray>> recorded;
  // tile_costs: each 8 x 8-pixel tile's thread-seconds (row-major, ceil(W / 8) x ceil(H / 8)
  // tiles): a map of what rays cost where on the screen, so a foveated frame's time can be
  // compared with what the same content costs at full resolution (tracer_bench's
  // content-weighted ray ratio).
  std::vector<double> tile_seconds;
};
struct points_trace {
  point_samples samples;
  trace_stats stats;
};
struct reference_trace {
  frame image;
  trace_stats stats;
};
// The tiles of trace_params::tile_seconds.
constexpr int reference_tile = 8;

// Traces every point the screen needs for this gaze (traced_point_mask with params.k):
// each casts r = params.spp rays (or its point_ray_rule count under params.ray_floor)
// through positions in the disc of radius p around it (params.disc_sampler; fixed per
// point: seeded by params.seed and the point's index), and a grid point (is_grid_point) its
// screen pixel's rays (params.sampler, seeded by the pixel; mirrored pattern
// n = mirror_x + 2 mirror_y casts the pixel's samples n r .. (n+1) r - 1).
points_trace trace_points(const scene& s, const camera& cam, const pointset& set, gaze_point gaze,
                          const trace_params& params);
// The same frame, its traced points found with `index` (make_traced_index(set, params.k),
// built once per set and k) instead of a scan of the table's screen border each frame.
points_trace trace_points(const scene& s, const camera& cam, const pointset& set, const traced_index& index,
                          gaze_point gaze, const trace_params& params);
// Traces exactly `points` (ascending indices of the set), each as trace_points traces it: a
// point gets the same rays for the same seed, pattern and gaze whatever else is traced. For
// frames that choose their points themselves (adaptive refinement, pipeline/adaptive.h).
points_trace trace_listed_points(const scene& s, const camera& cam, const pointset& set, std::vector<uint32_t> points,
                                 gaze_point gaze, const trace_params& params);
// Traces `points` (ascending, none of them in into.samples.traced) as trace_listed_points
// would, into a trace of the same set, gaze and params made earlier (by trace_listed_points
// or trace_points): their samples are written in place and merged into its traced list and
// rays, without clearing the set-sized arrays again. Returns the rays cast. Throws
// std::invalid_argument when `into` was placed otherwise or a point is listed twice.
uint64_t trace_more_points(const scene& s, const camera& cam, const pointset& set, const std::vector<uint32_t>& points,
                           gaze_point gaze, const trace_params& params, points_trace& into);

// Where each point a frame traces is seen from its centre: one primary ray through every point
// trace_points(s, cam, set, index, gaze, params) would trace (the same list, placement,
// mirroring and line cameras), no shading. What temporal reuse (pipeline/reuse.h) checks a
// stored sample against.
struct point_probe {
  std::vector<uint32_t> points;   // the points, ascending: trace_points' traced list
  canvas_offset offset;           // their placement (as point_samples::offset, mirror_x, mirror_y)
  bool mirror_x = false, mirror_y = false;
  std::vector<glm::vec2> screen;  // each point's screen position
  std::vector<glm::vec3> where;   // the hit's world position, or the ray's unit direction on a miss
  std::vector<float> distance;    // along the ray to the hit; +inf on a miss
  uint64_t rays = 0;              // one a point
};
// Where point p lands on the screen: the set placed at `offset` (canvas = screen + offset),
// then mirrored left-right and/or top-bottom (exact in float: the offset is whole pixels);
// and back, the canvas position of screen position `s` under the same placement.
glm::vec2 placed_position(const display_geometry& disp, const point& p, canvas_offset offset, bool mirror_x, bool mirror_y);
glm::vec2 canvas_position(const display_geometry& disp, glm::vec2 s, canvas_offset offset, bool mirror_x, bool mirror_y);

point_probe probe_points(const scene& s, const camera& cam, const pointset& set, const traced_index& index, gaze_point gaze,
                         const trace_params& params);

// The screen positions (pixels) of the rays trace_points cast for `samples` (its traced
// points, placement and mirroring, at `gaze`), in the order it cast them: params.spp per
// point, or each point's n(d) under params.ray_floor (point_ray_rule).
// The same rays without the tracer, for a bare intersection loop over them.
std::vector<glm::vec2> point_ray_positions(const pointset& set, const point_samples& samples, gaze_point gaze,
                                          const trace_params& params);

// Sample s of the Owen-scrambled Sobol (0,2)-sequence with scrambles `sx`, `sy`: a point
// of [0, 1)^2. The first 2^m samples put one sample in every elementary interval of
// area 2^-m (e.g. one per cell of a 2^(m/2) grid for even m).
glm::vec2 owen_sobol_2d(uint32_t s, uint32_t sx, uint32_t sy);

// Shirley and Chiu's concentric map of [0, 1)^2 onto the unit disc: area-preserving, so
// stratified points stay stratified.
glm::vec2 concentric_disc(glm::vec2 u);

// Full resolution: params.spp rays per pixel at params.sampler's positions inside it (with
// params.falloff, the first n(d) of them; the frame's rays count what was cast), from the
// pixel's sample m n on in TAA pattern m (trace_params::mirror_x, mirror_y).
reference_trace trace_reference(const scene& s, const camera& cam, int width, int height, const trace_params& params);

}  // namespace fov
