// The sweep fovbench runs: every configuration of scene x scale x gaze x spp x method x k
// traced and reconstructed by the shared renderer, timed against a full-resolution
// reference of the same scene, measured and written to results.csv.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "fov/flicker.h"
#include "fov/renderer.h"
#include "fov/speedup.h"
#include "report.h"

namespace fov {

// A gaze of the sweep, with the name its rows carry ("centre", "corner", "X_Y", "randomN").
struct named_gaze {
  std::string name;
  gaze_point at;
};

// "centre", "corner", "X,Y" or "N" (N gazes drawn with `seed`); throws usage_error naming --gazes.
std::vector<named_gaze> parse_gazes(const std::vector<std::string>& items, const display_geometry& d, uint64_t seed);

// A full-resolution reference of one scene at one spp and seed: the frame and what one
// trace of it took.
struct reference_frame {
  frame image;
  double ms = 0;
  uint64_t rays = 0;
  bool from_disk = false;  // read from the cache, not traced by this run
};

// A cached reference's sidecar (references/*.json): how it was traced and what it cost.
struct reference_meta {
  std::string scene, sampler, render_settings;
  uint32_t spp = 0;
  uint64_t seed = 0, rays = 0;
  double ms = 0;
};
// The largest sidecar read back.
constexpr uintmax_t max_reference_meta_bytes = 64 << 10;
// Reads a sidecar: a regular file of at most max_reference_meta_bytes holding one JSON
// object with every field above of its type (ms finite and >= 0, spp >= 1); throws
// std::runtime_error "FILE: reason" (naming the key) otherwise.
reference_meta read_reference_meta(const std::string& path);

// Converged references, cached in `dir` (EXR + JSON) so a resumed or repeated sweep
// reuses them: get() traces once per scene, size, spp and seed, and reads the files after.
class reference_cache {
 public:
  reference_cache(std::string dir, std::string scene, const display_geometry& d);
  const reference_frame& get(renderer& r, const render_params& base, uint32_t spp, uint64_t seed,
                             const std::function<void(const std::string&)>& say = {});
  // DIR/<scene slug>-<W>x<H>-spp<N>-seed<S>, without extension
  std::string file_base(uint32_t spp, uint64_t seed) const;
  // The converged frames along a temporal path (fov::converged_path; the renderer's set
  // decides the size, which must be the cache's), cached the same way, one EXR and sidecar
  // per frame (path_file_base), so the runs of a study that share a path trace it once.
  // `from_disk` (optional) says whether every frame was read back.
  std::vector<frame> path(renderer& r, const render_params& base, uint32_t spp, uint64_t seed, const flicker_params& f,
                          const std::function<void(const std::string&)>& say = {}, bool* from_disk = nullptr);
  // file_base plus -path<frames>-yaw<degrees per frame>-f<n>
  std::string path_file_base(uint32_t spp, uint64_t seed, const flicker_params& f, uint32_t n) const;

 private:
  // One cached frame, FILE.exr and its sidecar FILE.json: whether both are there; reading it
  // back (its sidecar must name these settings, or "FILE.json: not WHAT (SETTINGS)" is thrown,
  // and the image must have the display's size); writing it, the sidecar last.
  static bool cached(const std::string& file);
  std::pair<frame, reference_meta> read_cached(const std::string& file, const render_params& p, const std::string& settings,
                                               const std::string& what) const;
  void write_cached(const std::string& file, const frame& image, const render_params& p, const std::string& settings,
                    double ms) const;
  std::string dir_, scene_;
  display_geometry display_;
  std::map<std::pair<uint32_t, uint64_t>, reference_frame> refs_;
};




// The foveated set for one scale, read from --points-dir (DISPLAY-sS.fovset, with the
// fovea's suffix), generated and saved there when missing; checked against the display,
// the fovea and every k of the options. `say` reports the generation.
std::shared_ptr<const pointset> bench_pointset(const bench_options& o, const display_geometry& display, double scale,
                                               const std::function<void(const std::string&)>& say);

// The options' render settings that every row shares, as one text (its render_settings
// column): a results.csv holds rows of one setting only, so --resume can refuse others.
std::string render_settings_label(const render_params& p);

// Checks the options before anything is measured or written (usage_error for flags,
// runtime_error for missing scenes); returns the sweep's display.
display_geometry check_bench_options(const bench_options& o);

// Where the sweep reports: progress(done, todo, what) as it goes, line(text) for what the
// user must read on a line of its own (the plan, scene warnings, the C++ fallback).
struct bench_reporter {
  std::function<void(size_t done, size_t todo, const std::string& what)> progress;
  std::function<void(const std::string& text)> line;
};

// Runs the sweep into o.out/results.csv (rows already there are skipped with o.resume).
// Returns the number of rows measured.
size_t run_bench(const bench_options& o, const bench_reporter& report);

}  // namespace fov
