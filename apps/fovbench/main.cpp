// fovbench: sweeps point-set scale, method, k, rays per sample and gaze over scenes, and
// measures the speed/accuracy trade against full-resolution references, side by side.
#include <cmath>
#include <cstdlib>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "../common/cli.h"
#include "../common/compare_command.h"
#include "../common/jod_validation.h"
#include "../common/render_flags.h"
#include "bench.h"
#include "report.h"
#include "summary.h"
#include "sweep.h"
#include "yardstick.h"

namespace {

// Gazes may contain commas (X,Y): --gazes takes ';' between items, and a plain list of
// names with commas is split here when it holds no X,Y pair.
std::vector<std::string> split_gazes(const std::vector<std::string>& items) {
  std::vector<std::string> gazes;
  for (const std::string& g : items) {
    std::stringstream in(g);
    std::string part;
    std::vector<std::string> parts;
    while (std::getline(in, part, ',')) parts.push_back(part);
    bool pair = parts.size() == 2;
    for (const std::string& p : parts) pair = pair && !p.empty() && (std::isdigit(static_cast<unsigned char>(p[0])) || p[0] == '.');
    if (pair) gazes.push_back(g);
    else gazes.insert(gazes.end(), parts.begin(), parts.end());
  }
  return gazes;
}

}  // namespace

int main(int argc, char** argv) {
  fov::keep_frame_buffers_in_heap();
  CLI::App app{"fovbench: the speed/accuracy trade of foveated ray tracing, measured"};
  fov::bench_options o;
  o.methods = {fov::method::shepard};
  app.add_option("--scene", o.scenes, "Scene (repeat): builtin, builtin:cornell (a room where bounces matter), a glTF/OBJ file, env:IMAGE")->take_all();
  app.add_option("--display", o.display, fov::display_help());
  app.add_option("--viewing-distance", o.viewing_distance, "Eye-to-screen distance in display widths (replaces the display's)")
      ->check(CLI::Range(fov::min_viewing_distance, fov::max_viewing_distance));
  app.add_option("--scales", o.scales, "Point-set scales, e.g. 1.0,1.5,2.0")->delimiter(',');
  fov::add_label_option(app, "--methods", o.methods, fov::method_labels, "Reconstructions, e.g. nn,shepard")->delimiter(',');
  app.add_option("--k", o.ks, "Neighbours, e.g. 5,10,20 (nn always uses 1)")->delimiter(',');
  app.add_option("--spp", o.spps, "Rays per point and per reference pixel, e.g. 1,4,16,32")->delimiter(',');
  app.add_option("--gazes", o.gazes, "centre, corner, X,Y, or N (N seeded random gazes)")->delimiter(';');
  app.add_option("-o,--out", o.out, "Output directory (results.csv, plots, report.md, references/)");
  app.add_option("--points-dir", o.points_dir, "Where point sets are read, or generated when missing");
  fov::add_label_option(app, "--neighbours", o.neighbours, fov::knn_storage_labels,
                        "How the sets keep their neighbours: table (fastest to read) or cells (memory that grows with "
                        "the points; docs/fovgen.md); default: the table where it fits in memory, else cells");
  fov::add_label_option(app, "--acuity", o.acuity, fov::acuity_model_labels,
                        "The foveated sets' acuity model (fovgen --acuity, its default parameters; docs/schemes.md); "
                        "sets DISPLAY-ACUITY-sS.fovset");
  fov::add_label_option(app, "--sampler", o.sampler, fov::point_sampler_labels,
                        "The foveated sets' sampler (fovgen --sampler; docs/schemes.md); sets DISPLAY[-ACUITY]-SAMPLER-sS.fovset");
  fov::add_label_option(app, "--fovea", o.fovea, fov::fovea_layout_labels,
                        "The foveated sets' fovea (fovgen --fovea): darts (the thesis) or grid (DISPLAY-sS-grid.fovset)");
  app.add_option("--grid-spacing", o.grid_spacing,
                 "With --fovea grid: the largest model spacing (px, 0.5..4) with grid points (DISPLAY-sS-grid-P.fovset "
                 "unless 1)");
  fov::add_render_flags(app, o.render,
                        fov::flags_trace | fov::flags_reconstruct | fov::flags_device | fov::flags_view | fov::flags_pattern |
                            fov::flags_reuse);
  app.add_option("--taa-frames", o.taa_frames,
                 "Every row also in steady state: its errors after each N frames of TAA with a still view (rays in "
                 "--pattern's patterns), its time a frame's plus TAA's against full resolution with TAA, e.g. 16")
      ->delimiter(',');
  app.add_option("--frames", o.frames, "Timed repetitions per configuration, interleaved with the full-resolution frame (median, min, max)")
      ->capture_default_str();
  app.add_option("--reference-spp", o.reference_spp, "Rays per pixel of the converged reference every error is measured against")
      ->capture_default_str();
  fov::add_label_option(app, "--baselines", o.baselines, fov::baseline_labels,
                        "What is measured beside foveation: full (full resolution at each --spp), uniform (uniform sets)")
      ->delimiter(',');
  app.add_option("--uniform-fractions", o.uniform_fractions, "Pixel fractions of the uniform sets, e.g. 0.5,0.25")
      ->delimiter(',');
  app.add_option("--ray-floors", o.ray_floors,
                 "Falloff rows: the full pixel grid, rays falling from each --spp at the gaze to each floor below it as "
                 "the acuity model at each --scales value says (fov::ray_falloff; docs/speed-accuracy.md), e.g. 1,2")
      ->delimiter(',');
  app.add_option("--levels", o.levels,
                 "Adaptive rows (column density = adaptive): a nested set of these level scales, increasing "
                 "(DISPLAY-nS1-S2-....fovset in --points-dir, made when missing), e.g. 0.7,1.0,1.5,2.25,3.0")
      ->delimiter(',');
  app.add_option("--adaptive-thresholds", o.adaptive_thresholds,
                 "With --levels: a row per threshold, the nested set refined per frame where contrast reaches it times "
                 "the model's threshold (fovrender --adaptive-threshold; docs/adaptive.md), e.g. 1,0.5")
      ->delimiter(',');
  app.add_option("--point-ray-floors", o.point_ray_floors,
                 "Foveated rows also with each point's rays falling from each --spp at the gaze to each floor below it "
                 "(fov::point_ray_rule: the set's own model; with --fovea grid the hybrid), e.g. 1")
      ->delimiter(',');
  std::string shard;
  app.add_option("--shard", shard,
                 "Measure the I-th of N slices of the configurations (0 <= I < N; rows in -o/shard-I-of-N, references "
                 "shared in -o/references; default from SLURM_ARRAY_TASK_ID/COUNT); join with fovbench merge");
  app.add_flag("--no-sparse", o.no_sparse,
               "No sparse point sets (no foveated rows, no sets made): the --ray-floors rows and the baselines only");
  app.add_flag("--no-flip", [&o](int64_t) { o.flip = false; }, "Skip FLIP and the foveated FLIP (seconds per row)");
  app.add_flag("--no-jod", [&o](int64_t) { o.jod = false; }, "Skip JOD (FovVideoVDP; a third of a second per FOVE row)");
  fov::add_photometry_flags(app, o.photometry);
  app.add_option("--spread-limit", o.spread_limit, "Flag rows whose timing spread exceeds this fraction of the median")
      ->capture_default_str();
  app.add_option("--temporal-frames", o.temporal_frames,
                 "Frames of the camera path for flicker and its video JOD against converged frames (0: skip)");
  app.add_option("--temporal-fps", o.temporal_fps, "The display's frame rate along that path, for the video JOD")
      ->capture_default_str();
  app.add_flag("--resume", o.resume, "Skip configurations already in results.csv");
  bool yardstick = false;
  app.add_flag("--yardstick", yardstick,
               "Instead of the sweep: JOD of the foveated frames through TAA against full resolution with the same rays, "
               "still and moving, over the scales, beside the thesis's observers (yardstick.csv, .md, yardstick_jod)");
  const CLI::Validator finite(
      [](std::string& text) { return std::isfinite(std::strtod(text.c_str(), nullptr)) ? "" : "must be a finite number"; },
      "FINITE");
  app.add_option("--budget-psnr", o.budget_psnr, "Report the fastest configuration with PSNR >= this (dB)")->check(finite);
  app.add_option("--budget-foveated", o.budget_foveated, "... or with foveated error <= this")->check(finite);

  // fovbench compare TEST REFERENCE: every metric of two images, without a sweep.
  fov::compare_options co;
  CLI::App* compare = app.add_subcommand(
      "compare", "Compare two images: JOD (FovVideoVDP), PSNR/SSIM, FLIP and foveated FLIP by eccentricity band");
  compare->add_option("test", co.test, "Test image")->required();
  compare->add_option("reference", co.reference, "Reference image")->required();
  compare->add_option("--display", co.display, fov::display_help() + " (default: the images' size, v = 1)");
  compare->add_option("--viewing-distance", co.viewing_distance, "Eye-to-screen distance in display widths")
      ->check(CLI::Range(fov::min_viewing_distance, fov::max_viewing_distance));
  compare->add_option("--gaze", co.gaze, "X,Y in pixels, centre or corner")->capture_default_str();
  compare->add_flag("--json", co.json, "Print JSON");
  compare->add_flag("--no-flip", [&co](int64_t) { co.flip = false; }, "Skip FLIP and the foveated FLIP");
  compare->add_flag("--no-jod", [&co](int64_t) { co.jod = false; }, "Skip JOD (FovVideoVDP)");
  fov::add_photometry_flags(*compare, co.photometry);
  compare->add_option("--fps", co.fps, "Video: frames per second; TEST (and REFERENCE, else a still) number frames with %d");
  compare->add_option("--frames", co.frames, "Video: how many frames, from 0");
  compare->add_option("--flip-map", co.flip_map, "Write the FLIP map (grey = 255 x error)");
  compare->add_option("--foveated-flip-map", co.foveated_flip_map, "Write the foveated FLIP map");

  // fovbench merge DIR... -o OUT: a sharded sweep's shards in one results.csv and report.
  fov::merge_options mo;
  CLI::App* merge = app.add_subcommand("merge", "Join several runs' results.csv (a sharded sweep's shards) into one report");
  merge->add_option("inputs", mo.inputs, "results.csv files or directories holding one")->required();
  merge->add_option("-o,--output", mo.out, "Output directory (results.csv, figures, report.md)")->required();
  merge->add_option("--spread-limit", mo.spread_limit, "As the sweep's")->check(CLI::Range(0.0, 10.0));
  merge->add_option("--budget-psnr", mo.budget_psnr, "As the sweep's");
  merge->add_option("--budget-foveated", mo.budget_foveated, "As the sweep's");

  // fovbench summary RUN... -o OUT: one answer per display, from many runs.
  fov::summary_options so;
  CLI::App* summary = app.add_subcommand(
      "summary", "One answer per display: each scheme's equal-quality speedup at the cheapest full frame reaching "
                 "--target-jod, from many runs (displays, scenes, layouts), with speedup-vs-ppd figures");
  summary->add_option("inputs", so.inputs, "results.csv files or directories searched for them")->required();
  summary->add_option("-o,--output", so.out, "Output directory (summary.md, summary.csv, figures); must hold no summary.md")
      ->required();
  summary->add_option("--target-jod", so.target_jod, "The yardstick: the cheapest full frame reaching this JOD")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 10.0));

  // fovbench validate-jod DIR: the JOD metric against the published implementation's values.
  std::string validation_dir;
  CLI::App* validate = app.add_subcommand(
      "validate-jod", "FovVideoVDP here against the published implementation's values (a table; exit 1 beyond 0.1 JOD)");
  validate->add_option("dir", validation_dir, "A folder like ../shared/metric-validation (jod-reference.json and images)")
      ->required();

  return fov::run_tool("fovbench", app, argc, argv, [&]() -> int {
    if (compare->parsed()) {
      std::cout << fov::run_compare(co);
      return 0;
    }
    if (merge->parsed()) {
      if (!std::isnan(mo.budget_psnr) && !std::isnan(mo.budget_foveated)) throw fov::usage_error("give one budget");
      const size_t n = fov::merge_results(mo, argc, argv);
      std::cout << fmt::format("{} rows in {}/results.csv; figures and report.md there\n", n, mo.out);
      return 0;
    }
    if (summary->parsed()) {
      const fov::summary_result r = fov::write_summary(so, argc, argv);
      for (const std::string& why : r.warnings) std::cerr << "fovbench: warning: " << why << "\n";
      std::cout << fmt::format("{} answers from {} results.csv in {}/summary.md (and summary.csv, figures)\n", r.answers.size(),
                               r.files.size(), so.out);
      return 0;
    }
    if (validate->parsed()) {
      const fov::jod_validation v = fov::validate_jod(validation_dir);
      std::cout << fov::jod_validation_markdown(v);
      if (v.worst <= 0.1) return 0;
      std::cerr << fmt::format("fovbench: {}: a value differs from the published one by {:.3f} JOD (more than 0.1)\n",
                               validation_dir, v.worst);
      return 1;
    }
    fov::parse_shard(shard, app.count("--shard") > 0, o);
    // --reuse and its knobs make rows of their own (bench_options::reuse); every other row
    // traces every point.
    o.reuse = o.render.reuse;
    o.render.reuse = {};
    for (const char* knob : {"--reuse-fovea", "--reuse-threshold", "--reuse-max-age", "--reuse-budget", "--reuse-edges",
                             "--reuse-distance", "--reuse-view"})
      if (app.count(knob) && o.reuse.mode == fov::reuse_mode::none) throw fov::usage_error(std::string(knob) + " needs --reuse temporal");
    if (yardstick && o.reuse.mode != fov::reuse_mode::none) throw fov::usage_error("--reuse: --yardstick has no reuse rows");
    o.gazes = split_gazes(o.gazes);
    if (o.scenes.empty()) o.scenes = {"builtin"};
    if (yardstick && o.shard_count > 1) throw fov::usage_error("--yardstick runs whole: no --shard (or Slurm array)");
    if (yardstick && !o.taa_frames.empty()) throw fov::usage_error("--taa-frames: --yardstick runs its own TAA sequences");
    if (app.count("--pattern") && o.taa_frames.empty())
      throw fov::usage_error("--pattern applies to the steady-state rows: add --taa-frames");
    if (yardstick) {
      fov::bench_reporter quiet;
      quiet.line = [](const std::string& text) { std::cerr << "fovbench: " << text << "\n"; };
      quiet.progress = [](size_t, size_t, const std::string&) {};
      const std::vector<fov::yardstick_row> rows = fov::run_yardstick(o, quiet);
      std::cout << fmt::format("{} conditions in {}/yardstick.csv; yardstick.md and yardstick_jod in {}\n", rows.size(), o.out, o.out);
      return 0;
    }
    // The progress bar is drawn only on a terminal; every other message, and an error,
    // gets a line of its own.
    const auto start = std::chrono::steady_clock::now();
    const bool terminal = isatty(STDERR_FILENO);
    bool on_bar = false;
    auto end_bar = [&] {
      if (on_bar) std::cerr << "\n";
      on_bar = false;
    };
    fov::bench_reporter report;
    report.line = [&](const std::string& text) {
      end_bar();
      std::cerr << "fovbench: " << text << "\n";
    };
    report.progress = [&](size_t done, size_t todo, const std::string& what) {
      if (!terminal) return;
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double eta = done ? elapsed / double(done) * double(todo - done) : 0;
      const int bar = todo ? int(30 * done / todo) : 30;
      std::cerr << fmt::format("\r[{}{}] {}/{} {:<44.44} elapsed {:.0f}s, ETA {}", std::string(size_t(bar), '#'),
                               std::string(size_t(30 - bar), '.'), done, todo, what, elapsed,
                               done ? fmt::format("{:.0f}s", eta) : std::string("?"))
                << std::flush;
      on_bar = true;
    };
    try {
      fov::run_bench(o, report);
    } catch (...) {
      end_bar();
      throw;
    }
    end_bar();

    // Figures and the report from every row, this run's and earlier ones.
    const std::string dir = fov::results_dir(o), results = (std::filesystem::path(dir) / "results.csv").string();
    const std::vector<fov::result_row> rows = fov::read_results(results);
    for (const std::string& why : fov::write_bench_figures(rows, o, dir)) std::cerr << "fovbench: warning: " << why << "\n";
    fov::write_bench_report(rows, o, (std::filesystem::path(dir) / "report.md").string(), argc, argv);
    std::cout << fmt::format("{} rows in {}; figures and report.md in {}\n", rows.size(), results, dir);
    return 0;
  });
}
