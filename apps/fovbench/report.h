// fovbench's options, figures (pareto.png, error_by_eccentricity.png, speedup_vs_scale.png)
// and report.md, made from the rows of results.csv.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "fov/comparison.h"
#include "fov/renderer.h"
#include "fov/speedup.h"
#include "sweep.h"

namespace fov {

// What a user would do instead of foveating, measured beside it.
enum class baseline {
  full,     // the whole screen at full resolution with the sweep's rays per pixel (kind full)
  uniform,  // a uniform set of a fraction of the pixels, traced and reconstructed like a
            // foveated one (kind uniform: a lower resolution, upsampled by the same methods)
};
inline constexpr std::pair<const char*, baseline> baseline_labels[] = {{"full", baseline::full}, {"uniform", baseline::uniform}};

struct bench_options {
  std::vector<std::string> scenes;
  std::string display = "fove";  // a display spec (require_display)
  double viewing_distance = 0;   // display widths; 0: the display's own
  std::vector<double> scales{1.0};
  std::vector<method> methods;
  std::vector<uint32_t> ks{5};
  std::vector<uint32_t> spps{4};
  std::vector<std::string> gazes{"centre"};
  std::string out = "out/bench";
  std::string points_dir = "precomputed";
  // The foveated sets' fovea (fovgen --fovea, --grid-spacing): one per results.csv, like
  // the footprint.
  fovea_layout fovea = fovea_layout::darts;
  // The acuity model of the foveated sets (fovgen --acuity, its default parameters): their
  // files are named by it, and results.csv's `acuity` column says it.
  acuity_model acuity = acuity_model::wang_csf;
  point_sampler sampler = point_sampler::poisson;  // and their sampler (fovgen --sampler; column `sampler`)
  // How the sets keep their neighbours; without a value, the table where it fits in memory,
  // else k-NN cells (the same frames either way; results.csv's `neighbours` says which).
  std::optional<knn_storage> neighbours;
  double grid_spacing = dart_params{}.grid_spacing;
  // Settings every configuration shares (seed, shadows, texture footprint, RBF kernel and
  // shape, Renka, device, camera); method, k and spp come from the lists above.
  render_params render;
  // Every error is against a converged reference of this many Sobol rays per pixel; a
  // second one (another seed) measures its noise floor.
  uint32_t reference_spp = 256;
  std::vector<baseline> baselines{baseline::full};
  std::vector<double> uniform_fractions{0.5, 0.25};
  // Falloff rows (kind falloff): the full pixel grid, rays falling from each spp at the gaze
  // to each of these floors (below that spp) as the acuity model at each scale says
  // (fov::ray_falloff). Empty: none.
  std::vector<uint32_t> ray_floors;
  // Foveated rows also with each point's rays falling with eccentricity from each spp to
  // each of these floors (below that spp; fov::point_ray_rule, the set's own model), beside
  // the rows where every point casts spp. Empty: none.
  std::vector<uint32_t> point_ray_floors;
  bool no_sparse = false;  // no sparse sets (foveated rows): falloff rows and baselines only
  // Adaptive rows (issue 26; docs/adaptive.md): a nested set of these level scales
  // (increasing, finest first; DISPLAY-nS1-S2-....fovset in points_dir) refined per frame at
  // each threshold (render_params::adaptive), beside the fixed sets. Empty: none.
  std::vector<double> levels;
  std::vector<double> adaptive_thresholds;
  // Every configuration also in steady state under TAA (issue 24): its errors after each of
  // these many frames of a still view (renderer::steady_state, full_steady_state; the
  // pattern is render.pattern), its time a frame's plus TAA's, against full-resolution
  // frames with TAA. Empty: single frames only.
  std::vector<uint32_t> taa_frames;
  // Sharding (fovbench --shard I/N): this run measures configurations i with i % count ==
  // index of the sweep's list; its rows go to OUT/shard-I-of-N/, references are shared in
  // OUT/references. count 1: the whole sweep, rows in OUT.
  uint32_t shard_index = 0, shard_count = 1;
  bool flip = true;  // FLIP and the foveated FLIP (seconds per row on a large screen)
  bool jod = true;   // JOD (FovVideoVDP), foveated at the row's gaze and not
  display_photometry photometry;  // the display's light, for JOD
  comparison_params judging() const {
    comparison_params p;
    p.flip = flip, p.jod = jod, p.photometry = photometry;
    return p;
  }
  uint32_t frames = 3;
  // A row whose timing spread (max - min) exceeds this fraction of its median is flagged
  // "noisy" in results.csv and counted in the report.
  double spread_limit = 0.25;
  uint32_t temporal_frames = 0;
  // Reuse rows (issue 28; column reuse = temporal): each fixed set's single-frame
  // configuration (no ray floor) also along the temporal path with these settings
  // (measure_reuse: every frame traced and reusing in turn), timed there against the set fully
  // traced and against full resolution. mode none: no such rows; eyes is refused (one eye).
  reuse_params reuse;
  double temporal_fps = 60;  // the display's frame rate along the temporal path, for its video JOD
  bool resume = false;
  double budget_psnr = std::numeric_limits<double>::quiet_NaN();
  double budget_foveated = std::numeric_limits<double>::quiet_NaN();
};

// Where a run's results.csv, figures and report go: OUT, or OUT/shard-I-of-N.
std::string results_dir(const bench_options& o);

// --shard I/N, or Slurm's array variables when no --shard is given (SLURM_ARRAY_TASK_ID less
// SLURM_ARRAY_TASK_MIN, of SLURM_ARRAY_TASK_COUNT); usage_error naming the flag or variable.
void parse_shard(const std::string& text, bool given, bench_options& o);

// fovbench merge: the rows of several runs' results.csv (a sharded sweep's shards) in one
// results.csv, figures and report. Each input is a results.csv or a directory holding one.
struct merge_options {
  std::vector<std::string> inputs;
  std::string out;
  double spread_limit = 0.25;
  double budget_psnr = std::numeric_limits<double>::quiet_NaN();
  double budget_foveated = std::numeric_limits<double>::quiet_NaN();
};
// Refuses inputs measured differently (display, footprint, fovea, render settings,
// reference) or holding the same configuration twice; writes OUT/results.csv (never over an
// existing one), the figures and report.md. Returns the rows merged.
size_t merge_results(const merge_options& m, int argc, char** argv);

// The goal's question (issue 24, item 5), asked of each foveated scheme on its own: at the
// JOD of a full-resolution frame (the yardstick), the fastest of the scheme's configurations
// that reaches it, priced as the verdict prices one (its paired ratios chained with the
// ladder's, 95 % bootstrap interval), or, when none does, the scheme's best JOD. Means over
// the gazes; per sweep part (scene, single frames or one steady state), yardstick and scheme.
enum class scheme {
  sparse,            // foveated rows of fixed density with the thesis's darts fovea (any rays per point)
  hybrid,            // foveated rows with a pixel-grid fovea (--fovea grid)
  falloff,           // the full pixel grid at a foveated sampling rate
  lower_resolution,  // uniform sets: what a user would do instead, judged the same way
  adaptive,          // foveated rows of density adaptive: a nested set refined per frame
};
inline constexpr std::pair<const char*, scheme> scheme_labels[] = {{"sparse", scheme::sparse},
                                                                   {"hybrid", scheme::hybrid},
                                                                   {"falloff", scheme::falloff},
                                                                   {"lower-resolution", scheme::lower_resolution},
                                                                   {"adaptive", scheme::adaptive}};
struct scheme_answer {
  std::string scene, taa_frames, taa_pattern, display;  // where: the sweep part and its display
  std::string integrator = "direct";                    // and how its rays were traced (integrator_text)
  double ppd = 0, pixels = 0;                           // the display's pixels per degree and pixel count
  double noise_floor_jod = 0;                           // the reference's own (a second reference against it)
  double target_jod = 0;
  double yardstick_spp = 0;  // the yardstick: full resolution at this spp
  double yardstick_jod = 0, yardstick_ms = 0, yardstick_rays = 0;
  fov::scheme scheme = scheme::sparse;
  bool reached = false;  // a configuration of the scheme reaches the yardstick's JOD
  // The fastest configuration reaching it, or (not reached) the one with the best JOD.
  std::string best;  // its label, e.g. "s0.50 shepard 4-1spp k5"
  double best_jod = 0, best_ms = 0, best_rays = 0, best_points = 0;
  speedup_interval speedup;  // against the yardstick; NaN when not reached
  std::string source;        // the results.csv it came from (set by the caller)
};
// Every answer of one run's rows, at every full-resolution frame as the yardstick (target_jod NaN).
std::vector<scheme_answer> scheme_answers_by_level(const std::vector<result_row>& rows);
// The goal's target: its yardstick is the cheapest full frame (fewest spp) reaching this JOD.
constexpr double goal_target_jod = 9.5;
// The answers at the goal's yardstick, chosen per scene, steady state and display over all
// of `by_level` (which may come from several runs): the fewest spp whose full frame reaches
// target_jod, else the best full frame's spp. Sets target_jod.
std::vector<scheme_answer> at_goal(const std::vector<scheme_answer>& by_level, double target_jod);

// The goal at a display's pixels per degree, where it names one: 1.5x at FOVE's 22,
// 5x at about 50 (45..55), 10x at 70 or more; NaN between.
double goal_speedup(double ppd);
// The title of an answer's sweep part: its scene, and its steady state if any.
std::string answer_title(const scheme_answer& a);

// The answers as a markdown table per sweep part: display, yardstick and one cell per scheme.
std::string scheme_answers_markdown(const std::vector<scheme_answer>& answers);

// A scene as titles name it: its file name, "env:" kept ("builtin" stays "builtin").
std::string short_scene(const std::string& scene);

// The figures (plot.h); returns one line per figure that could not be drawn (the caller warns).
std::vector<std::string> write_bench_figures(const std::vector<result_row>& rows, const bench_options& o, const std::string& dir);
void write_bench_report(const std::vector<result_row>& rows, const bench_options& o, const std::string& path, int argc,
                        char** argv);

}  // namespace fov
