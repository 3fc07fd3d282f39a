#include "bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <memory>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "../common/cli.h"
#include "../common/image_io.h"
#include "fov/dart_throwing.h"
#include "fov/files.h"
#include "fov/flicker.h"
#include "fov/comparison.h"
#include "fov/knn_table.h"
#include "fov/pointset_io.h"
#include "fov/random.h"

namespace fov {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

std::string number(double v) {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.6g}", v);
}

std::string slug(const std::string& scene) {
  std::string s = fs::path(scene.substr(scene.rfind(':') == std::string::npos ? 0 : scene.rfind(':') + 1)).stem().string();
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '-';
  return (scene.rfind("env:", 0) == 0 ? "env-" : "") + s;
}

// One row of the sweep: a foveated or uniform configuration, or a full-resolution frame.
struct config {
  size_t scene;
  row_kind kind;
  size_t set;        // foveated and falloff: the scale's index (adaptive: the threshold's); uniform: the fraction's; full: unused
  size_t gaze;
  method how;
  uint32_t k, spp;
  uint32_t floor;  // falloff, and foveated under --point-ray-floors: the ray floor (0: spp everywhere)
  uint32_t taa;    // 0: a single frame; N: the steady state after N frames of TAA (--taa-frames)
  bool adaptive;   // foveated: the nested set refined per frame at threshold `set` (--adaptive-thresholds)
  bool reuse;      // foveated, fixed: along the temporal path with bench_options::reuse (a reuse row)
  std::string key;
};

std::string fraction_text(double f) { return fmt::format("{:.4f}", f); }

// A nested set's level scales as results.csv's levels column says them.
std::string levels_text(const std::vector<double>& scales) {
  std::string out;
  for (double s : scales) out += (out.empty() ? "" : ";") + fmt::format("{:.2f}", s);
  return out;
}

// A reuse row's settings as its reuse_settings column says them (every knob, so that rows
// of other settings are other rows).
std::string reuse_settings_text(const reuse_params& r) {
  return fmt::format("fovea={:g} threshold={:g} max_age={} budget={} view={:g} edges={} distance={}", r.fovea_deg, r.threshold,
                     r.max_age, r.budget, r.view_deg, label_of(reuse_edges_labels, r.edges),
                     label_of(reuse_distance_labels, r.distance));
}

// The cells that say which row a configuration is (its key), written the same way for
// --resume's key and for the row itself.
result_row identity_row(const bench_options& o, const std::vector<named_gaze>& gazes, const config& c) {
  result_row r;
  r.cells = {{"scene", o.scenes[c.scene]}, {"gaze", gazes[c.gaze].name}, {"kind", row_kind_name(c.kind)}, {"spp", std::to_string(c.spp)}};
  if (c.taa) r.cells["taa_frames"] = std::to_string(c.taa), r.cells["taa_pattern"] = label_of(ray_pattern_labels, o.render.pattern);
  if (c.kind == row_kind::full) {
    r.cells["method"] = "full", r.cells["pixel_fraction"] = fraction_text(1);
  } else if (c.kind == row_kind::falloff) {
    r.cells["method"] = "falloff", r.cells["pixel_fraction"] = fraction_text(1);
    r.cells["scale"] = fmt::format("{:.2f}", o.scales[c.set]), r.cells["ray_floor"] = std::to_string(c.floor);
  } else {
    r.cells["method"] = method_name(c.how), r.cells["k"] = std::to_string(c.k);
    if (c.floor > 0) r.cells["ray_floor"] = std::to_string(c.floor);
    if (c.kind == row_kind::foveated && c.adaptive) {
      r.cells["density"] = "adaptive", r.cells["adaptive_threshold"] = fmt::format("{:g}", o.adaptive_thresholds[c.set]);
      r.cells["levels"] = levels_text(o.levels);
    } else if (c.kind == row_kind::foveated) {
      r.cells["scale"] = fmt::format("{:.2f}", o.scales[c.set]), r.cells["density"] = "fixed";
      if (c.reuse) r.cells["reuse"] = "temporal", r.cells["reuse_settings"] = reuse_settings_text(o.reuse);
    } else {
      r.cells["pixel_fraction"] = fraction_text(o.uniform_fractions[c.set]);
    }
  }
  return r;
}

// A set's ray floors at one spp: 0 (every point casts spp, the thesis), then for a foveated
// set each --point-ray-floors value below spp (rays falling with eccentricity to it).
std::vector<uint32_t> point_floors(const bench_options& o, row_kind kind, uint32_t spp) {
  std::vector<uint32_t> out{0};
  if (kind == row_kind::foveated)
    for (uint32_t floor : o.point_ray_floors)
      if (floor < spp) out.push_back(floor);
  return out;
}

std::vector<config> all_configs(const bench_options& o, const std::vector<named_gaze>& gazes) {
  std::vector<config> all;
  // Each configuration as a single frame, then in steady state after each --taa-frames N.
  std::vector<uint32_t> taas{0};
  taas.insert(taas.end(), o.taa_frames.begin(), o.taa_frames.end());
  auto add = [&](size_t sc, row_kind kind, size_t set, size_t g, method how, uint32_t k, uint32_t spp, uint32_t floor,
                 bool adaptive = false) {
    auto put = [&](config c) {
      c.key = identity_row(o, gazes, c).key();
      if (std::none_of(all.begin(), all.end(), [&](const config& d) { return d.key == c.key; })) all.push_back(c);
    };
    for (uint32_t taa : taas) put(config{sc, kind, set, g, how, k, spp, floor, taa, adaptive, false, ""});
    // A fixed set's single frame also along the temporal path with reuse.
    if (o.reuse.mode == reuse_mode::temporal && kind == row_kind::foveated && !adaptive && floor == 0)
      put(config{sc, kind, set, g, how, k, spp, floor, 0, false, true, ""});
  };
  const bool uniform = std::count(o.baselines.begin(), o.baselines.end(), baseline::uniform) > 0;
  const bool full = std::count(o.baselines.begin(), o.baselines.end(), baseline::full) > 0;
  for (size_t sc = 0; sc < o.scenes.size(); ++sc) {
    for (const auto& [kind, sets] : {std::pair<row_kind, size_t>{row_kind::foveated, o.no_sparse ? 0 : o.scales.size()},
                                     {row_kind::uniform, uniform ? o.uniform_fractions.size() : 0}})
      for (size_t si = 0; si < sets; ++si)
        for (size_t g = 0; g < gazes.size(); ++g)
          for (uint32_t spp : o.spps)
            for (uint32_t floor : point_floors(o, kind, spp))
              for (method how : o.methods)
                for (uint32_t k : how == method::nn ? std::vector<uint32_t>{1} : o.ks) add(sc, kind, si, g, how, k, spp, floor);
    for (size_t ti = 0; ti < o.adaptive_thresholds.size(); ++ti)
      for (size_t g = 0; g < gazes.size(); ++g)
        for (uint32_t spp : o.spps)
          for (method how : o.methods)
            for (uint32_t k : how == method::nn ? std::vector<uint32_t>{1} : o.ks)
              add(sc, row_kind::foveated, ti, g, how, k, spp, 0, true);
    for (size_t si = 0; si < o.scales.size(); ++si)
      for (size_t g = 0; g < gazes.size(); ++g)
        for (uint32_t spp : o.spps)
          for (uint32_t floor : o.ray_floors)
            if (floor < spp) add(sc, row_kind::falloff, si, g, method::nn, 0, spp, floor);
    if (full)
      for (size_t g = 0; g < gazes.size(); ++g)
        for (uint32_t spp : o.spps) add(sc, row_kind::full, 0, g, method::nn, 0, spp, 0);
  }
  return all;
}

// The model of the foveated sets at one scale: the display and the acuity model of the
// options (its default parameters). Their names and their generation both start here.
spacing_model bench_model(const bench_options& o, const display_geometry& display, double scale) {
  spacing_model model;
  model.display = display, model.scale = scale;
  model.acuity.model = o.acuity;
  return model;
}

// How the foveated sets' points are placed: the options' sampler and fovea.
dart_params bench_darts(const bench_options& o) {
  dart_params darts;
  darts.fovea = o.fovea, darts.grid_spacing = o.grid_spacing, darts.sampler = o.sampler;
  return darts;
}

// The foveated sets' layout as results.csv and the set's file name say it (fov::fovea_label).
std::string fovea_text(const bench_options& o) { return fovea_label(bench_darts(o)); }

// Throws unless a loaded set has the options' acuity model and sampler.
void require_scheme(const bench_options& o, const pointset& set, const std::string& path) {
  const acuity_params want = bench_model(o, set.model.display, set.model.scale).acuity;
  if (!same_acuity(set.model.acuity, want))
    throw std::runtime_error(
        fmt::format("{}: made with acuity {}, not {}", path, acuity_label(set.model.acuity), acuity_label(want)));
  if (set.darts.sampler != o.sampler)
    throw std::runtime_error(fmt::format("{}: placed by sampler {}, not {}", path, label_of(point_sampler_labels, set.darts.sampler),
                                         label_of(point_sampler_labels, o.sampler)));
}

// Where the set for one scale lives in --points-dir.
std::string bench_pointset_path(const bench_options& o, const display_geometry& display, double scale) {
  return (fs::path(o.points_dir) / pointset_file_name(bench_model(o, display, scale), bench_darts(o))).string();
}

// Where the nested set of --levels lives in --points-dir.
std::string bench_nested_path(const bench_options& o, const display_geometry& display) {
  return (fs::path(o.points_dir) /
          pointset_file_name(bench_model(o, display, o.levels.front()), dart_params{}, {o.levels.rbegin(), o.levels.rend()}))
      .string();
}

}  // namespace

namespace {

// Sets fovbench makes keep their table where it fits in memory, else k-NN cells (the same
// neighbours; results.csv's `neighbours` says which a row read).
knn_storage bench_storage(const bench_options& o, const display_geometry& display, uint32_t k) {
  if (o.neighbours) return *o.neighbours;
  return knn_table_memory_problem(display, k).empty() ? knn_storage::table : knn_storage::cells;
}

// Every --k the sweep reads must be within the set's stored k.
void require_ks(const bench_options& o, const pointset& set, const std::string& path) {
  for (uint32_t k : o.ks)
    if (k > stored_k(set)) throw usage_error(fmt::format("--k {} exceeds the k = {} of {}", k, stored_k(set), path));
}

}  // namespace

std::shared_ptr<const pointset> bench_pointset(const bench_options& o, const display_geometry& display, double scale,
                                               const std::function<void(const std::string&)>& say) {
  const std::string path = bench_pointset_path(o, display, scale);
  if (!fs::exists(path)) {
    say(fmt::format("generating {}", path));
    make_output_dir(o.points_dir);
    const knn_storage storage = bench_storage(o, display, knn_params{}.k);
    if (storage == knn_storage::cells)
      say(fmt::format("the k-NN table of a {} set would not fit in memory: the set keeps k-NN cells", display_name(display)));
    save_pointset(path, generate_pointset(bench_model(o, display, scale), bench_darts(o), {}, storage));
  }
  pointset loaded = load_pointset(path);
  // A set stored the other way is kept the way asked for: its neighbours built from its points.
  const knn_storage storage = bench_storage(o, display, stored_k(loaded));
  if (storage != loaded.storage()) {
    say(fmt::format("{}: building its k-NN {} (--neighbours)", path, label_of(knn_storage_labels, storage)));
    knn_params kp;
    kp.k = stored_k(loaded);
    if (storage == knn_storage::table)
      if (const std::string why = knn_table_memory_problem(display, kp.k); !why.empty())
        throw usage_error("--neighbours table: " + why);
    build_neighbours(loaded, kp, storage);
  }
  auto set = std::make_shared<const pointset>(std::move(loaded));
  if (fovea_label(set->darts) != fovea_text(o))
    throw std::runtime_error(fmt::format("{}: its fovea is {}, not {}", path, fovea_label(set->darts), fovea_text(o)));
  if (display_name(set->model.display) != display_name(display) || set->model.scale != scale)
    throw std::runtime_error(fmt::format("{}: made for {} at s = {}, not {} at s = {}", path, display_name(set->model.display),
                                         set->model.scale, display_name(display), scale));
  require_scheme(o, *set, path);
  require_ks(o, *set, path);
  return set;
}

reference_cache::reference_cache(std::string dir, std::string scene, const display_geometry& d)
    : dir_(std::move(dir)), scene_(std::move(scene)), display_(d) {}

std::string reference_cache::file_base(uint32_t spp, uint64_t seed) const {
  return (fs::path(dir_) / fmt::format("{}-{}x{}-spp{}-seed{}", slug(scene_), display_.width, display_.height, spp, seed)).string();
}

std::string reference_cache::path_file_base(uint32_t spp, uint64_t seed, const flicker_params& f, uint32_t n) const {
  return file_base(spp, seed) + fmt::format("-path{}-yaw{:g}-f{}", f.frames, f.yaw_deg_per_frame, n);
}

bool reference_cache::cached(const std::string& file) {
  std::error_code ec;
  return fs::exists(file + ".exr", ec) && fs::exists(file + ".json", ec);
}

std::pair<frame, reference_meta> reference_cache::read_cached(const std::string& file, const render_params& p,
                                                              const std::string& settings, const std::string& what) const {
  const reference_meta m = read_reference_meta(file + ".json");
  if (m.render_settings != settings || m.sampler != label_of(pixel_sampler_labels, p.reference_sampler) || m.spp != p.spp ||
      m.seed != p.seed)
    throw std::runtime_error(fmt::format("{}.json: not {} ({}); remove it or use another -o", file, what, settings));
  frame image = read_frame(file + ".exr");
  if (image.width != display_.width || image.height != display_.height)
    throw std::runtime_error(fmt::format("{}.exr: {}x{}, not {}x{}", file, image.width, image.height, display_.width,
                                         display_.height));
  return {std::move(image), m};
}

void reference_cache::write_cached(const std::string& file, const frame& image, const render_params& p,
                                   const std::string& settings, double ms) const {
  write_frame(image, file + ".exr");
  const std::string text = json{{"scene", scene_}, {"spp", p.spp}, {"seed", p.seed}, {"ms", ms}, {"rays", image.rays},
                                {"sampler", label_of(pixel_sampler_labels, p.reference_sampler)},
                                {"render_settings", settings}}.dump(2) + "\n";
  write_file_atomic(file + ".json", text.data(), text.size());  // last: a frame without it is traced again
}

std::vector<frame> reference_cache::path(renderer& r, const render_params& base, uint32_t spp, uint64_t seed,
                                         const flicker_params& f, const std::function<void(const std::string&)>& say,
                                         bool* from_disk) {
  render_params p = base;
  p.spp = spp, p.seed = seed, p.reference_sampler = pixel_sampler::sobol;  // as converged_path traces
  // Each frame's settings name the path and the frame: a file of another path or frame is refused.
  auto settings = [&](uint32_t n) {
    return render_settings_label(p) + fmt::format(" path_frames={} path_yaw={:g} path_frame={}", f.frames, f.yaw_deg_per_frame, n);
  };
  bool on_disk = true;
  for (uint32_t n = 0; n < f.frames && on_disk; ++n) on_disk = cached(path_file_base(spp, seed, f, n));
  if (from_disk) *from_disk = on_disk;
  std::vector<frame> frames;
  if (on_disk) {
    for (uint32_t n = 0; n < f.frames; ++n) {
      frame image = read_cached(path_file_base(spp, seed, f, n), p, settings(n), fmt::format("frame {} of this path", n)).first;
      image.depth = {};  // as converged_path gives it: colour is all the video JOD reads
      frames.push_back(std::move(image));
    }
    return frames;
  }
  if (say) say(fmt::format("converged temporal path, {} frames at {} spp, seed {}", f.frames, spp, seed));
  frames = converged_path(r, base, spp, seed, f);
  for (uint32_t n = 0; n < f.frames; ++n) {
    if (frames[n].width != display_.width || frames[n].height != display_.height)
      throw std::logic_error("reference_cache::path: the renderer's set is not the cache's display");
    write_cached(path_file_base(spp, seed, f, n), frames[n], p, settings(n), 0);
  }
  return frames;
}

const reference_frame& reference_cache::get(renderer& r, const render_params& base, uint32_t spp, uint64_t seed,
                                            const std::function<void(const std::string&)>& say) {
  const auto id = std::make_pair(spp, seed);
  auto it = refs_.find(id);
  if (it != refs_.end()) return it->second;
  const std::string file = file_base(spp, seed);
  render_params p = base;
  p.spp = spp;
  p.seed = seed;
  const std::string settings = render_settings_label(p);
  reference_frame ref;
  if (cached(file)) {
    auto [image, m] = read_cached(file, p, settings, "a reference of these settings");
    ref.image = std::move(image);
    ref.ms = m.ms;
    ref.rays = m.rays;
    ref.from_disk = true;
  } else {
    if (say) say(fmt::format("reference {} spp, seed {}", spp, seed));
    frame_timing t;
    ref.image = r.reference(display_.width, display_.height, p, &t).image;
    ref.ms = t.trace_ms;
    ref.rays = ref.image.rays;
    write_cached(file, ref.image, p, settings, ref.ms);
  }
  return refs_.emplace(id, std::move(ref)).first->second;
}



reference_meta read_reference_meta(const std::string& path) {
  const json j = json::parse(read_input_file(path, max_reference_meta_bytes, "reference sidecar"), nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw std::runtime_error(fmt::format("{}: not a JSON object", path));
  auto field = [&](const char* key, bool (json::*is)() const noexcept, const char* type) -> const json& {
    if (!j.contains(key) || !(j[key].*is)()) throw std::runtime_error(fmt::format("{}: \"{}\" must be {}", path, key, type));
    return j[key];
  };
  reference_meta m;
  m.scene = field("scene", &json::is_string, "a string").get<std::string>();
  m.sampler = field("sampler", &json::is_string, "a string").get<std::string>();
  m.render_settings = field("render_settings", &json::is_string, "a string").get<std::string>();
  m.seed = field("seed", &json::is_number_unsigned, "a whole number >= 0").get<uint64_t>();
  m.rays = field("rays", &json::is_number_unsigned, "a whole number >= 0").get<uint64_t>();
  const uint64_t spp = field("spp", &json::is_number_unsigned, "a whole number >= 0").get<uint64_t>();
  if (spp < 1 || spp > max_spp) throw std::runtime_error(fmt::format("{}: \"spp\" {} lies outside 1..{}", path, spp, max_spp));
  m.spp = uint32_t(spp);
  m.ms = field("ms", &json::is_number, "a number").get<double>();
  if (!(m.ms >= 0) || !std::isfinite(m.ms)) throw std::runtime_error(fmt::format("{}: \"ms\" must be finite and >= 0", path));
  return m;
}

std::vector<named_gaze> parse_gazes(const std::vector<std::string>& items, const display_geometry& d, uint64_t seed) {
  std::vector<named_gaze> out;
  for (const std::string& g : items) {
    char* end = nullptr;
    const long n = std::strtol(g.c_str(), &end, 10);
    if (!g.empty() && *end == '\0') {  // N random gazes, seeded
      if (n < 1 || n > 100) throw usage_error(fmt::format("--gazes: {} random gazes is outside 1..100", n));
      rng r(stream_seed(seed, 0x6a7e));
      for (long i = 0; i < n; ++i) {
        const double x = std::round(r.uniform() * d.width), y = std::round(r.uniform() * d.height);
        out.push_back({fmt::format("random{}", i + 1), {x, y}});
      }
      continue;
    }
    const gaze_point at = require_gaze("--gazes", g, d);
    out.push_back({g.find(',') == std::string::npos ? g : fmt::format("{:g}_{:g}", at.x, at.y), at});
  }
  return out;
}


std::string render_settings_label(const render_params& p) {
  auto point = [](const std::optional<glm::vec3>& v) {
    return v ? fmt::format("{:g},{:g},{:g}", v->x, v->y, v->z) : std::string("-");  // -: the scene camera's
  };
  // The disc sampler is named only when it is not the thesis's, so results of sweeps made
  // before it existed still resume.
  const std::string disc = p.disc_sampler == pixel_sampler::random ? "" : std::string(" disc_sampler=") +
                                                                             label_of(pixel_sampler_labels, p.disc_sampler);
  // The integrator is always named: glTF materials shade by the metallic-roughness model
  // since it came, so references and results of glTF scenes made before it do not resume.
  std::string integrator = p.method == integrator::path ? fmt::format("integrator=path bounces={}", p.bounces)
                                                         : std::string("integrator=direct");
  if (!p.env_light.empty()) integrator += " env_light=" + p.env_light;
  return fmt::format("seed={} sampler={}{} {} exposure={:g} sun_dir={} sun_irradiance={} shadows={} renka={} rbf_kernel={} "
                     "rbf_shape={:g} hfov={:g} eye={} look_at={} up={}",
                     p.seed, label_of(pixel_sampler_labels, p.reference_sampler), disc, integrator, p.exposure_ev, point(p.sun_direction),
                     point(p.sun_irradiance), p.shadows ? 1 : 0, p.reconstruct.renka ? 1 : 0, label_of(rbf_kernel_labels, p.reconstruct.kernel),
                     p.reconstruct.shape, p.view.hfov_deg, point(p.view.eye), point(p.view.target), point(p.view.up));
}

std::shared_ptr<const pointset> bench_nested_pointset(const bench_options& o, const display_geometry& display,
                                                      const std::function<void(const std::string&)>& say) {
  const std::string path = bench_nested_path(o, display);
  uint32_t k = knn_params{}.k;
  for (uint32_t ok : o.ks) k = std::max(k, ok);
  if (!fs::exists(path)) {
    say(fmt::format("generating {}", path));
    knn_params kp;
    kp.k = k;
    make_output_dir(o.points_dir);
    const knn_storage storage = bench_storage(o, display, kp.k);
    save_pointset(path, generate_nested_pointset(bench_model(o, display, o.levels.front()), o.levels, dart_params{}, kp, storage));
  }
  auto set = std::make_shared<const pointset>(load_pointset(path));
  std::vector<double> finest_first(set->level_scales.rbegin(), set->level_scales.rend());
  require_scheme(o, *set, path);
  if (display_name(set->model.display) != display_name(display) || finest_first != o.levels)
    throw std::runtime_error(fmt::format("{}: made for {} with levels {}, not {} with levels {}", path,
                                         display_name(set->model.display), levels_text(finest_first), display_name(display),
                                         levels_text(o.levels)));
  if (set->storage() != bench_storage(o, display, stored_k(*set)))
    throw std::runtime_error(fmt::format("{}: keeps its neighbours as {}, not as --neighbours asks", path,
                                         label_of(knn_storage_labels, set->storage())));
  require_ks(o, *set, path);
  return set;
}

display_geometry check_bench_options(const bench_options& o) {
  for (const auto& [flag, scales] : {std::pair<const char*, const std::vector<double>&>{"--scales", o.scales}, {"--levels", o.levels}})
    for (double s : scales)
      if (!(s >= 0.5 && s <= 10)) throw usage_error(fmt::format("{}: {} is outside 0.5..10", flag, s));
  for (uint32_t k : o.ks)
    if (k < 1 || k > max_knn) throw usage_error(fmt::format("--k: {} is outside 1..{}", k, max_knn));
  for (uint32_t s : o.spps)
    if (s < 1 || s > max_spp) throw usage_error(fmt::format("--spp: {} is outside 1..{}", s, max_spp));
  if (o.spps.empty() || o.ks.empty() || o.methods.empty() || o.scales.empty() || o.gazes.empty())
    throw usage_error("--scales, --methods, --k, --spp and --gazes each need at least one value");
  if (o.frames < 1 || o.frames > 100) throw usage_error("--frames must lie in 1..100");
  if (!valid_grid_spacing(o.grid_spacing))
    throw usage_error(fmt::format("--grid-spacing must lie in {}..{} pixels (got {})", min_grid_spacing, max_grid_spacing,
                                  o.grid_spacing));
  if (o.fovea != fovea_layout::grid && o.grid_spacing != dart_params{}.grid_spacing)
    throw usage_error("--grid-spacing needs --fovea grid");
  if (o.sampler != point_sampler::poisson && o.fovea != fovea_layout::darts)
    throw usage_error("--fovea grid needs --sampler poisson (a lattice has its own fovea)");
  if (o.reference_spp < 1 || o.reference_spp > max_spp)
    throw usage_error(fmt::format("--reference-spp must lie in 1..{} (got {})", max_spp, o.reference_spp));
  for (uint32_t s : o.spps)
    if (s >= o.reference_spp)
      throw usage_error(fmt::format("--reference-spp {} must exceed every --spp (got {}): a reference must be better than "
                                    "what it measures", o.reference_spp, s));
  for (double f : o.uniform_fractions) {
    bool power = false;
    for (int i = 1; i <= 16; ++i) power = power || f == std::ldexp(1.0, -i);
    if (!power) throw usage_error(fmt::format("--uniform-fractions: {} is not 1/2, 1/4, 1/8, ... (0.5, 0.25, 0.125, ...)", f));
  }
  if (std::count(o.baselines.begin(), o.baselines.end(), baseline::uniform) && o.uniform_fractions.empty())
    throw usage_error("--baselines uniform needs at least one --uniform-fractions value");
  if (!(o.spread_limit > 0 && o.spread_limit <= 10)) throw usage_error("--spread-limit must lie in (0, 10]");
  for (const auto& [flag, floors] : {std::pair<const char*, const std::vector<uint32_t>&>{"--ray-floors", o.ray_floors},
                                      {"--point-ray-floors", o.point_ray_floors}})
    for (uint32_t floor : floors) {
      if (floor < 1 || floor > max_spp) throw usage_error(fmt::format("{}: {} is not a ray count in 1..{}", flag, floor, max_spp));
      if (std::none_of(o.spps.begin(), o.spps.end(), [&](uint32_t spp) { return floor < spp; }))
        throw usage_error(fmt::format("{} {}: no --spp above it to fall from", flag, floor));
    }
  if (o.no_sparse && !o.point_ray_floors.empty()) throw usage_error("--point-ray-floors: --no-sparse leaves no point set to trace");
  for (uint32_t n : o.taa_frames)
    if (n < 2 || n > max_taa_frames)
      throw usage_error(fmt::format("--taa-frames: {} is outside 2..{} (a single frame is every row's own)", n, max_taa_frames));
  if (o.temporal_frames == 1 || o.temporal_frames > 200) throw usage_error("--temporal-frames must be 0 or 2..200");
  if (!(o.temporal_fps >= 8 && o.temporal_fps <= 1000)) throw usage_error("--temporal-fps must lie in 8..1000");
  if (!std::isnan(o.budget_psnr) && !std::isnan(o.budget_foveated)) throw usage_error("give one budget");
  const std::string problem = validate(o.render);
  if (!problem.empty()) throw usage_error(problem);
  const display_geometry display = require_display("--display", o.display, o.viewing_distance);
  const size_t gazes = parse_gazes(o.gazes, display, o.render.seed).size();
  // The video JOD keeps the converged path of every gaze (colour, 12 bytes a pixel).
  if (o.temporal_frames >= 2 && o.jod)
    if (const std::string why = memory_problem(uint64_t(gazes) * o.temporal_frames * uint64_t(display.width) * display.height * 12,
                                               fmt::format("the converged temporal paths ({} gazes x {} frames)", gazes,
                                                           o.temporal_frames));
        !why.empty())
      throw usage_error("--temporal-frames: " + why + " (fewer frames, or --no-jod)");
  if (o.no_sparse && o.ray_floors.empty()) throw usage_error("--no-sparse leaves no foveated scheme: add --ray-floors");
  if (o.reuse.mode == reuse_mode::eyes) throw usage_error("--reuse eyes: fovbench renders one eye (use --reuse temporal)");
  if (o.reuse.mode == reuse_mode::temporal) {
    if (o.temporal_frames < 2) throw usage_error("--reuse temporal needs --temporal-frames 2..200 (the path it is measured along)");
    if (o.no_sparse) throw usage_error("--reuse: --no-sparse leaves no point set to reuse the samples of");
    if (const std::string why = validate(o.reuse); !why.empty()) throw usage_error(why);
  }
  if (!o.levels.empty() || !o.adaptive_thresholds.empty()) {
    if (o.levels.empty()) throw usage_error("--adaptive-thresholds needs --levels (the nested set's scales)");
    if (o.adaptive_thresholds.empty()) throw usage_error("--levels needs --adaptive-thresholds (the adaptive rows' thresholds)");
    if (const std::string why = levels_problem(o.levels); !why.empty()) throw usage_error(why);
    for (double t : o.adaptive_thresholds)
      if (!(t >= 0 && t <= max_adaptive_threshold))
        throw usage_error(fmt::format("--adaptive-thresholds: {} is outside 0..{:g}", t, max_adaptive_threshold));
    if (o.fovea == fovea_layout::grid) throw usage_error("--levels: a nested set's fovea is darts; drop --fovea grid");
    if (o.sampler != point_sampler::poisson) throw usage_error("--levels: a nested set is darts; drop --sampler");
    if (o.no_sparse) throw usage_error("--levels: --no-sparse leaves no point set to trace");
  }
  // Sets that will be generated need a --points-dir this process can write in: known now,
  // not after the references are traced.
  for (double s : o.scales)
    if (!o.no_sparse && !fs::exists(bench_pointset_path(o, display, s))) {
      require_output_dir("--points-dir", o.points_dir);
    }
  if (!o.levels.empty() && !fs::exists(bench_nested_path(o, display))) require_output_dir("--points-dir", o.points_dir);
  // -o/references must be (or become) a directory.
  if (const fs::path refs = fs::path(o.out) / "references"; fs::exists(refs) && !fs::is_directory(refs))
    throw usage_error(fmt::format("-o {}: {} is not a directory", o.out, refs.string()));
  for (const std::string& scene : o.scenes) {  // fail before any output, not an hour in
    const std::string file = scene.rfind("env:", 0) == 0 ? scene.substr(4) : scene;
    if (is_builtin_scene(scene)) continue;
    if (const std::string why = input_file_problem(file); !why.empty())
      throw std::runtime_error(fmt::format("--scene {}: {}", scene, why));
  }
  return display;
}

namespace {

const char* band_suffix[5] = {"fovea", "5_10", "10_20", "20_30", "periphery"};

// Per-repetition values joined by ';' (speedup_samples, ladder_samples).
std::string samples_text(const std::vector<double>& v) {
  std::string out;
  for (double x : v) out += (out.empty() ? "" : ";") + fmt::format("{:.6g}", x);
  return out;
}

void put_errors(result_row& row, const comparison& m) {
  const error_report& e = m.error;
  row.cells["psnr"] = number(e.overall.psnr), row.cells["ssim"] = number(e.overall.ssim);
  for (size_t b = 0; b < 5; ++b) {
    row.cells[std::string("psnr_") + band_suffix[b]] = e.bands[b].pixels ? number(e.bands[b].psnr) : "";
    row.cells[std::string("ssim_") + band_suffix[b]] = e.bands[b].pixels ? number(e.bands[b].ssim) : "";
    if (m.has_flip) row.cells[std::string("flip_") + band_suffix[b]] = number(m.flip.flip.bands[b]);
  }
  row.cells["foveated_error"] = number(e.foveated_error), row.cells["foveated_psnr"] = number(e.foveated_psnr);
  std::string profile;
  for (double v : e.profile_rmse) profile += (profile.empty() ? "" : ";") + fmt::format("{:.5f}", v);
  row.cells["error_profile"] = profile;
  if (m.has_jod) row.cells["jod"] = number(m.jod.jod), row.cells["jod_nonfoveated"] = number(m.jod.jod_nonfoveated);
  if (!m.has_flip) return;
  row.cells["flip"] = number(m.flip.flip.mean), row.cells["flip_p99"] = number(m.flip.flip.p99);
  row.cells["foveated_flip"] = number(m.flip.foveated.mean);
  row.cells["foveated_flip_p99"] = number(m.flip.foveated.p99);
  row.cells["foveated_flip_worst_band"] = number(m.flip.foveated.worst_band);
}

void put_floor(result_row& row, const comparison& floor, uint32_t reference_spp) {
  row.cells["reference_spp"] = std::to_string(reference_spp);
  row.cells["noise_floor_psnr"] = number(floor.error.overall.psnr);
  row.cells["noise_floor_psnr_fovea"] = number(floor.error.bands[0].psnr);
  row.cells["noise_floor_foveated_error"] = number(floor.error.foveated_error);
  if (floor.has_flip) {
    row.cells["noise_floor_flip"] = number(floor.flip.flip.mean);
    row.cells["noise_floor_flip_fovea"] = number(floor.flip.flip.bands[0]);
    row.cells["noise_floor_foveated_flip"] = number(floor.flip.foveated.mean);
  }
  if (floor.has_jod) {
    row.cells["noise_floor_jod"] = number(floor.jod.jod);
    row.cells["noise_floor_jod_nonfoveated"] = number(floor.jod.jod_nonfoveated);
  }
  for (size_t b = 0; b < 5; ++b) row.cells[std::string("geometry_") + band_suffix[b]] = number(floor.geometry[b]);
}

void put_timing(result_row& row, const paired_timing& t, double spread_limit) {
  row.cells["frame_ms"] = number(t.frame_ms.median), row.cells["frame_ms_lo"] = number(t.frame_ms.min);
  row.cells["frame_ms_hi"] = number(t.frame_ms.max);
  row.cells["full_ms"] = number(t.full_ms.median), row.cells["full_ms_lo"] = number(t.full_ms.min);
  row.cells["full_ms_hi"] = number(t.full_ms.max);
  row.cells["speedup"] = number(t.speedup.median), row.cells["speedup_lo"] = number(t.speedup.min);
  row.cells["speedup_hi"] = number(t.speedup.max);
  const bool noisy = (t.frame_ms.max - t.frame_ms.min) > spread_limit * t.frame_ms.median ||
                     (t.full_ms.max - t.full_ms.min) > spread_limit * t.full_ms.median;
  row.cells["timing_flag"] = noisy ? "noisy" : "";
}

}  // namespace

namespace {

// The configurations results.csv already holds (--resume), after checking that its rows were
// measured the way this run would measure them: one footprint, fovea, render setting and
// reference per file.
std::set<std::string> resumed_keys(const bench_options& o, const display_geometry& display, const std::string& results_path) {
  std::set<std::string> done;
  std::error_code ec;
  if (!fs::exists(results_path, ec)) return done;
  if (!o.resume)
    throw std::runtime_error(fmt::format("{} exists: add --resume to continue that sweep, or choose another -o", results_path));
  const std::string footprint = texture_footprint_name(o.render.footprint), fovea = fovea_text(o),
                    settings = render_settings_label(o.render);
  for (const result_row& r : read_results(results_path)) {
    if (r.text("texture_footprint") != footprint)
      throw std::runtime_error(fmt::format("{}: its rows were traced with --texture-footprint {}, not {}; use another -o",
                                           results_path, r.text("texture_footprint"), footprint));
    if (r.text("display") != display_name(display))
      throw std::runtime_error(fmt::format("{}: its rows were measured on display {}, not {}; use another -o", results_path,
                                           r.text("display"), display_name(display)));
    if (r.text("fovea") != fovea)
      throw std::runtime_error(fmt::format("{}: its foveated sets have --fovea {}, not {}; use another -o", results_path,
                                           r.text("fovea"), fovea));
    if (r.text("acuity") != acuity_model_name(o.acuity))
      throw std::runtime_error(fmt::format("{}: its foveated sets have --acuity {}, not {}; use another -o", results_path,
                                           r.text("acuity"), acuity_model_name(o.acuity)));
    if (r.text("sampler") != label_of(point_sampler_labels, o.sampler))
      throw std::runtime_error(fmt::format("{}: its foveated sets have --sampler {}, not {}; use another -o", results_path,
                                           r.text("sampler"), label_of(point_sampler_labels, o.sampler)));
    if (r.text("render_settings") != settings)
      throw std::runtime_error(fmt::format("{}: its rows were measured with {}, not {}; use another -o", results_path,
                                           r.text("render_settings"), settings));
    if (r.text("reference_spp") != std::to_string(o.reference_spp))
      throw std::runtime_error(fmt::format("{}: its rows were measured against a {}-spp reference, not {}; use another -o",
                                           results_path, r.text("reference_spp"), o.reference_spp));
    done.insert(r.key());
  }
  return done;
}

// What the sweep shares while it measures: the options, the configurations, the rows done
// and the writer (made with the first row: a run that fails before leaves no results.csv).
struct sweep_state {
  sweep_state(const bench_options& options, const bench_reporter& reporter, display_geometry d)
      : o(options), report(reporter), display(d) {}
  const bench_options& o;
  const bench_reporter& report;
  display_geometry display;
  std::vector<named_gaze> gazes;
  std::vector<config> all;
  std::set<std::string> done;
  std::string results_path;
  size_t todo = 0, measured_rows = 0;
  std::optional<results_writer> writer;

  void say(const std::string& what) const { report.progress(measured_rows, todo, what); }
  std::function<void(const std::string&)> sayer() const {
    return [this](const std::string& what) { say(what); };
  }
  bool needed(const std::function<bool(const config&)>& match) const {
    return std::any_of(all.begin(), all.end(), [&](const config& c) { return match(c) && !done.count(c.key); });
  }
  void finish(const config& c, const result_row& row) {
    if (!writer) writer.emplace(results_path);
    writer->append(row);
    done.insert(c.key);
    ++measured_rows;
  }
};

// Every scene the sweep still needs, loaded and its camera set up before anything is
// measured: a broken scene listed last fails now, not after an hour of the others.
std::vector<std::shared_ptr<const scene>> load_needed_scenes(const sweep_state& st) {
  std::vector<std::shared_ptr<const scene>> scenes(st.o.scenes.size());
  for (size_t sc = 0; sc < st.o.scenes.size(); ++sc) {
    if (!st.needed([&](const config& c) { return c.scene == sc; })) continue;
    st.say("loading " + st.o.scenes[sc]);
    scenes[sc] = load_scene(st.o.scenes[sc], st.o.render.env_light);
    for (const std::string& w : scenes[sc]->warnings()) st.report.line("warning: " + w);
    setup_camera(*scenes[sc], st.o.render.view);
  }
  return scenes;
}

// The k of every cached-weight configuration the sweep alternates: each method with cached
// weights at each k.
std::vector<uint32_t> cached_weight_ks(const bench_options& o) {
  std::vector<uint32_t> ks;
  for (method how : o.methods)
    if (cached_weights_method(how)) ks.insert(ks.end(), o.ks.begin(), o.ks.end());
  return ks;
}

// The sweep's render settings, keeping every cached-weight configuration it alternates, so no
// timed frame computes weights again.
render_params sweep_render(const bench_options& o) {
  render_params p = o.render;
  p.weight_caches = std::clamp(uint32_t(cached_weight_ks(o).size()), cl_reconstructor::default_weight_caches,
                               cl_reconstructor::max_weight_caches);
  return p;
}

// One scene's measurements: its renderer, converged references and noise floors, and the
// full-resolution frames timed beside the foveated and uniform ones.
class scene_sweep {
 public:
  scene_sweep(sweep_state& st, size_t sc, std::shared_ptr<const scene> scn)
      : st_(st), o_(st.o), sc_(sc), r_(std::move(scn), sweep_render(st.o)),
        references_((fs::path(st.o.out) / "references").string(), st.o.scenes[sc], st.display),
        eye_{st.display, 1.0, acuity_params{}} {
    r_.warm_up_reference(st.display.width, st.display.height, o_.render);  // textures read and MIP-mapped on first use
    const auto [seed_a, seed_b] = converged_seeds(o_.render.seed);
    truth_ = &references_.get(r_, o_.render, o_.reference_spp, seed_a, st.sayer()).image;
    second_ = &references_.get(r_, o_.render, o_.reference_spp, seed_b, st.sayer()).image;
  }

  // The foveated sets, then the uniform baseline's: traced and reconstructed the same way.
  void measure_sets(row_kind kind) {
    const size_t sets = kind == row_kind::foveated ? o_.scales.size() : o_.uniform_fractions.size();
    for (size_t si = 0; si < sets; ++si) {
      if (!st_.needed([&](const config& c) { return c.scene == sc_ && c.kind == kind && c.set == si && !c.adaptive; }))
        continue;
      use_set(kind, si);
      for (size_t g = 0; g < st_.gazes.size(); ++g)
        for (uint32_t spp : o_.spps)
          for (uint32_t floor : point_floors(o_, kind, spp))
            measure_group(kind, si, g, spp, floor, false);
    }
    // The nested set, refined per frame at each threshold.
    if (kind != row_kind::foveated || !st_.needed([&](const config& c) { return c.scene == sc_ && c.adaptive; })) return;
    r_.use_pointset(bench_nested_pointset(o_, st_.display, st_.sayer()));
    if (const std::string warning = r_.device_warning(); !warning.empty()) st_.report.line(warning);
    for (size_t ti = 0; ti < o_.adaptive_thresholds.size(); ++ti)
      for (size_t g = 0; g < st_.gazes.size(); ++g)
        for (uint32_t spp : o_.spps) measure_group(kind, ti, g, spp, 0, true);
  }

  // The full-resolution baseline: every timing of its frames gathered while the sets were
  // measured (more when none was), errors at each gaze.
  void measure_full() {
    for (const config& c : st_.all) {
      if (c.scene != sc_ || c.kind != row_kind::full || st_.done.count(c.key)) continue;
      full_frame& f = fulls_[c.spp];
      while (f.ms.size() < o_.frames) {
        st_.say(fmt::format("timing full resolution spp={}", c.spp));
        time_full(c.spp);
      }
      const std::vector<double>& ladder_samples = ladder(c.taa > 0).at(c.spp);  // timed first: every full row reads the same timings
      const named_gaze& gp = st_.gazes[c.gaze];
      st_.say(fmt::format("measuring full resolution {} spp={}{}", gp.name, c.spp, taa_text(c)));
      result_row row = row_for(c);
      row.cells["points_traced"] = "", row.cells["rays"] = std::to_string(f.image.rays);
      row.cells["rays_cast"] = std::to_string(f.cast.total());
      row.cells["trace_ms"] = number(summarise(f.ms).median), row.cells["reconstruct_ms"] = "0";
      // With TAA: each timing of the frame plus its TAA resolve's, timed right after it.
      const std::vector<double> ms = c.taa ? plus(f.ms, f.taa_ms) : f.ms;
      put_timing(row, pair_timings(ms, ms), o_.spread_limit);
      row.cells["trace_cpu_ms"] = number(summarise(f.cpu_ms).median), row.cells["reconstruct_cpu_ms"] = "0";
      row.cells["full_cpu_ms"] = row.cells["trace_cpu_ms"];
      row.cells["ladder_samples"] = samples_text(ladder_samples);
      if (c.taa) {
        render_params p = o_.render;
        p.spp = c.spp;
        put_errors(row, compare_images(r_.full_steady_state(st_.display, gp.at, p, c.taa), *truth_, eye_, gp.at, o_.judging()));
      } else {
        put_errors(row, compare_images(f.image, *truth_, eye_, gp.at, o_.judging()));
      }
      st_.finish(c, row);
    }
  }

  // The full pixel grid at a foveated sampling rate: each configuration's frames timed
  // interleaved with the full-resolution frame at its spp (the paired speedup), its errors.
  void measure_falloff() {
    for (const config& c : st_.all) {
      if (c.scene != sc_ || c.kind != row_kind::falloff || st_.done.count(c.key)) continue;
      const named_gaze& gp = st_.gazes[c.gaze];
      render_params p = o_.render;
      p.spp = c.spp;
      ray_falloff f;
      f.model = eye_, f.model.scale = o_.scales[c.set], f.gaze = gp.at, f.floor = c.floor;
      const std::string what =
          fmt::format("falloff s={:.2f} {} spp={} floor={}{}", o_.scales[c.set], gp.name, c.spp, c.floor, taa_text(c));
      std::vector<double> full_ms, full_cpu, frame_ms, frame_cpu;
      frame image;
      ray_counts cast;  // the same every repetition: the rays do not depend on the timing
      for (uint32_t n = 0; n < o_.frames; ++n) {
        st_.say(fmt::format("timing {} ({}/{})", what, n + 1, o_.frames));
        full_ms.push_back(time_full(c.spp));
        full_cpu.push_back(fulls_[c.spp].cpu_ms.back());
        if (c.taa) full_ms.back() += fulls_[c.spp].taa_ms.back();
        frame_timing t;
        const double cpu = process_cpu_ms();
        reference_trace traced = r_.falloff_frame(f, p, &t);
        frame_cpu.push_back(process_cpu_ms() - cpu);
        frame_ms.push_back(t.trace_ms);
        cast = t.cast;
        if (c.taa) frame_ms.back() += time_resolve(traced.image);
        if (image.rgb.empty()) image = std::move(traced.image);
      }
      if (c.taa) image = r_.full_steady_state(st_.display, gp.at, p, c.taa, &f);
      st_.say(fmt::format("measuring {}", what));
      result_row row = row_for(c);
      row.cells["points_traced"] = "", row.cells["rays"] = std::to_string(image.rays);
      row.cells["rays_cast"] = std::to_string(cast.total());
      row.cells["trace_ms"] = number(summarise(frame_ms).median), row.cells["reconstruct_ms"] = "0";
      const paired_timing paired = pair_timings(frame_ms, full_ms);
      put_timing(row, paired, o_.spread_limit);
      row.cells["speedup_samples"] = samples_text(paired.ratios);
      row.cells["trace_cpu_ms"] = number(summarise(frame_cpu).median), row.cells["reconstruct_cpu_ms"] = "0";
      row.cells["full_cpu_ms"] = number(summarise(full_cpu).median);
      put_errors(row, compare_images(image, *truth_, eye_, gp.at, o_.judging()));
      st_.finish(c, row);
    }
  }

 private:
  // Full-resolution frames at each spp: the image (deterministic) and every timing of it.
  struct full_frame {
    frame image;
    std::vector<double> ms, cpu_ms;  // wall and process CPU time of every timing
    std::vector<double> taa_ms;      // with --taa-frames: a TAA resolve of it, timed right after each
    ray_counts cast;                 // every ray it cast, by kind
  };

  static std::vector<double> plus(const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> out(a);
    for (size_t i = 0; i < out.size() && i < b.size(); ++i) out[i] += b[i];
    return out;
  }
  static std::string taa_text(const config& c) { return c.taa ? fmt::format(" taa={}", c.taa) : ""; }

  // One TAA resolve of a full-grid frame (taa_resolve, C++: what a full-resolution renderer
  // adds per frame) into a history of the sweep's own, timed; the first one, which passes the
  // frame through, is untimed.
  double time_resolve(const frame& image) {
    const gaze_point centre{st_.display.width / 2.0, st_.display.height / 2.0};
    if (!full_history_.valid) taa_resolve(full_history_, image, r_.cam(), st_.display, centre, o_.render.temporal);
    const auto t0 = std::chrono::steady_clock::now();
    taa_resolve(full_history_, image, r_.cam(), st_.display, centre, o_.render.temporal);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }

  // How the set in use keeps its neighbours: its table, or cells (bench_pointset).
  std::string neighbours_label() const {
    const pointset* set = r_.current_set();
    return set ? label_of(knn_storage_labels, set->storage()) : "";
  }

  void use_set(row_kind kind, size_t si) {
    if (kind == row_kind::foveated) {
      r_.use_pointset(bench_pointset(o_, st_.display, o_.scales[si], st_.sayer()));
    } else {
      st_.say(fmt::format("uniform set of {} of the pixels", fraction_text(o_.uniform_fractions[si])));
      knn_params kp;  // every k the sweep reads
      kp.k = 1;
      for (uint32_t k : o_.ks) kp.k = std::max(kp.k, k);
      pointset uniform = uniform_pointset(st_.display, o_.uniform_fractions[si], kp, bench_storage(o_, st_.display, kp.k));
      r_.use_pointset(std::make_shared<const pointset>(std::move(uniform)));
    }
    if (const std::string warning = r_.device_warning(); !warning.empty()) st_.report.line(warning);
  }

  // The second reference against the first, per gaze.
  const comparison& floor_at(size_t g) {
    if (!floors_.count(g)) {
      st_.say(fmt::format("noise floor at {}", st_.gazes[g].name));
      floors_[g] = compare_images(*second_, *truth_, eye_, st_.gazes[g].at, o_.judging());
    }
    return floors_[g];
  }

  result_row row_for(const config& c) {
    result_row row = identity_row(o_, st_.gazes, c);
    const named_gaze& gp = st_.gazes[c.gaze];
    row.cells.insert({{"gaze_x", number(gp.at.x)}, {"gaze_y", number(gp.at.y)},
                      {"texture_footprint", texture_footprint_name(o_.render.footprint)}, {"fovea", fovea_text(o_)},
                      {"acuity", acuity_model_name(o_.acuity)}, {"sampler", label_of(point_sampler_labels, o_.sampler)},
                      {"display", display_name(st_.display)}, {"ppd", number(pixels_per_degree(st_.display))},
                      {"device", r_.device()}, {"frames", std::to_string(o_.frames)},
                      {"neighbours", c.kind == row_kind::foveated || c.kind == row_kind::uniform ? neighbours_label() : ""},
                      {"render_settings", render_settings_label(o_.render)},
                      {"integrator", label_of(integrator_labels, o_.render.method)},
                      {"bounces", o_.render.method == integrator::path ? std::to_string(o_.render.bounces) : ""},
                      {"full_rays", std::to_string(uint64_t(st_.display.width) * st_.display.height * c.spp)}});
    put_floor(row, floor_at(c.gaze), o_.reference_spp);
    return row;
  }

  double time_full(uint32_t spp) {
    render_params p = o_.render;
    p.spp = spp;
    frame_timing t;
    const double cpu = process_cpu_ms();
    reference_trace traced = r_.reference(st_.display.width, st_.display.height, p, &t);
    full_frame& f = fulls_[spp];
    f.cpu_ms.push_back(process_cpu_ms() - cpu);
    f.ms.push_back(t.trace_ms);
    if (!o_.taa_frames.empty()) f.taa_ms.push_back(time_resolve(traced.image));
    if (f.image.rgb.empty()) f.image = std::move(traced.image), f.cast = t.cast;
    return t.trace_ms;
  }

  // The ladder: --frames repetitions, each timing the full-resolution frame at every spp of
  // the sweep back to back (ascending); per repetition, each spp's time over the lowest's.
  // Chained with a configuration's paired ratio, it prices the configuration against a
  // full-resolution frame at another spp without comparing times taken minutes apart.
  // With TAA (taa): each frame's time plus its TAA resolve's, timed right after it.
  const std::map<uint32_t, std::vector<double>>& ladder(bool taa) {
    if (ladder_.empty()) {
      std::vector<uint32_t> spps = o_.spps;
      std::sort(spps.begin(), spps.end());
      for (uint32_t f = 0; f < o_.frames; ++f) {
        st_.say(fmt::format("timing the full-resolution ladder ({}/{})", f + 1, o_.frames));
        double lowest = 0, lowest_taa = 0;
        for (uint32_t spp : spps) {
          const double ms = time_full(spp);
          const double with_taa = o_.taa_frames.empty() ? ms : ms + fulls_[spp].taa_ms.back();
          if (spp == spps.front()) lowest = ms, lowest_taa = with_taa;
          ladder_[spp].push_back(ms / lowest);
          ladder_taa_[spp].push_back(with_taa / lowest_taa);
        }
      }
    }
    return taa ? ladder_taa_ : ladder_;
  }

  // Every configuration of one set, gaze and spp still to do: one trace, every method timed
  // interleaved with the full-resolution frame, then each measured and written. A method's
  // single-frame and steady-state (TAA) rows share its timings: with TAA rows each
  // repetition reconstructs with TAA, the single frame's time leaving TAA's out.
  //
  // An adaptive group (the nested set in use, si the threshold's index) traces and refines
  // once per k (the refinement reads the coarser levels' k neighbours) and reconstructs each
  // method from its k's trace. The view is still, so every repetition after the first keeps
  // the first one's refinement (as a still view does) and times tracing the levels it chose.
  void measure_group(row_kind kind, size_t si, size_t g, uint32_t spp, uint32_t floor, bool adaptive) {
    std::vector<const config*> here;
    for (const config& c : st_.all)
      if (c.scene == sc_ && c.kind == kind && c.set == si && c.gaze == g && c.spp == spp && c.floor == floor &&
          c.adaptive == adaptive && !st_.done.count(c.key))
        here.push_back(&c);
    if (here.empty()) return;
    const std::string what = adaptive                    ? fmt::format("adaptive T={:g}", o_.adaptive_thresholds[si])
                             : kind == row_kind::foveated ? fmt::format("s={:.2f}{}", o_.scales[si], floor ? fmt::format(" floor={}", floor) : "")
                                                          : fmt::format("uniform {}", fraction_text(o_.uniform_fractions[si]));
    const std::string scene = slug(o_.scenes[sc_]);
    const named_gaze& gp = st_.gazes[g];
    render_params p = o_.render;
    p.spp = spp;
    p.ray_floor = floor;
    if (adaptive) p.adaptive.enabled = true, p.adaptive.threshold = o_.adaptive_thresholds[si];
    const bool with_taa = std::any_of(here.begin(), here.end(), [](const config* c) { return c->taa > 0; });
    // The reconstructions to time: each method and k once, whatever rows it has.
    using recon = std::pair<method, uint32_t>;
    std::vector<recon> recons;
    std::vector<uint32_t> ks;
    uint32_t widest = 0;
    for (const config* c : here) {
      widest = std::max(widest, c->k);
      if (std::find(ks.begin(), ks.end(), c->k) == ks.end()) ks.push_back(c->k);
      if (std::find(recons.begin(), recons.end(), recon{c->how, c->k}) == recons.end()) recons.push_back({c->how, c->k});
    }
    // One untimed trace at the largest k read gives every method its colours (a point's
    // rays do not depend on k); each method's first launch is untimed too.
    st_.say(fmt::format("tracing {} {} {} spp={}", scene, what, gp.name, spp));
    p.reconstruct.k = widest;
    frame_timing untimed;
    point_samples samples;
    std::map<uint32_t, adaptive_trace> refined;  // adaptive: each k's
    if (adaptive) {
      for (uint32_t k : ks) {
        p.reconstruct.k = k;
        refined[k] = r_.trace_refined(gp.at, p, untimed);
      }
      for (const recon& m : recons) {  // each method's first launch, untimed
        p.reconstruct.how = m.first, p.reconstruct.k = m.second;
        r_.reconstruct_refined(refined[m.second], gp.at, p, untimed);
      }
    } else {
      samples = r_.trace(gp.at, p, untimed).samples;
      for (const recon& m : recons) {
        p.reconstruct.how = m.first, p.reconstruct.k = m.second;
        r_.prepare(samples, p);
      }
    }
    // One rebuild of a set's frame: a fixed set's samples, or the refined levels at k.
    auto rebuild = [&](const render_params& q, frame_timing& t) -> const frame& {
      return adaptive ? r_.reconstruct_refined(refined[q.reconstruct.k], gp.at, q, t) : r_.reconstruct(samples, gp.at, q, t);
    };
    if (with_taa) {  // a TAA history to blend with: the first resolve only passes the frame through
      frame_timing t;
      p.taa = true;
      rebuild(p, t);
    }
    // Interleaved: each repetition times the full-resolution frame, every k's trace and
    // every method's reconstruction once, so slow phases of a shared machine hit all of
    // them alike and each speedup is a ratio of neighbouring runs.
    std::vector<double> full_ms, full_taa_ms, full_cpu;
    std::map<uint32_t, std::vector<double>> trace_ms, trace_cpu;
    std::map<recon, std::vector<double>> reconstruct_ms, taa_ms, reconstruct_cpu;
    std::map<uint32_t, uint64_t> rays, points, cast;
    std::map<uint32_t, std::vector<uint64_t>> level_rays;  // adaptive: each k's rays per level
    for (uint32_t f = 0; f < o_.frames; ++f) {
      st_.say(fmt::format("timing {} {} {} spp={} ({}/{})", scene, what, gp.name, spp, f + 1, o_.frames));
      full_ms.push_back(time_full(spp));
      full_cpu.push_back(fulls_[spp].cpu_ms.back());
      if (with_taa) full_taa_ms.push_back(fulls_[spp].taa_ms.back());
      for (uint32_t k : ks) {
        p.reconstruct.k = k;
        frame_timing t;
        const double cpu = process_cpu_ms();
        if (adaptive) refined[k] = r_.trace_refined(gp.at, p, t);
        else r_.trace(gp.at, p, t);
        trace_cpu[k].push_back(process_cpu_ms() - cpu);
        trace_ms[k].push_back(t.trace_ms);
        rays[k] = t.rays, points[k] = t.points_traced, cast[k] = t.cast.total();
        if (adaptive) level_rays[k] = t.refinement.rays_per_level;
      }
      for (const recon& m : recons) {
        p.reconstruct.how = m.first, p.reconstruct.k = m.second;
        p.taa = with_taa;
        frame_timing t;
        const double cpu = process_cpu_ms();
        rebuild(p, t);
        reconstruct_cpu[m].push_back(process_cpu_ms() - cpu);
        reconstruct_ms[m].push_back(t.reconstruct_ms);
        taa_ms[m].push_back(t.taa_ms);
      }
    }
    p.taa = false;
    for (const config* c : here) {
      const recon m{c->how, c->k};
      if (c->reuse) {
        st_.say(fmt::format("reuse along the path {} {} {} {} k={} spp={}", scene, what, gp.name, method_name(c->how), c->k, spp));
        measure_reuse_row(*c, p, summarise(reconstruct_ms[m]).median);
        continue;
      }
      st_.say(fmt::format("measuring {} {} {} {} k={} spp={}{}", scene, what, gp.name, method_name(c->how), c->k, spp, taa_text(*c)));
      p.reconstruct.how = c->how, p.reconstruct.k = c->k;
      frame_timing t;
      const frame image = c->taa ? r_.steady_state(gp.at, p, c->taa) : rebuild(p, t);
      if (const std::string w = weight_fallback_warning(t.weights, c->how); !w.empty())  // once per row
        std::cerr << fmt::format("fovbench: {} {} {} k={}: {}\n", scene, what, gp.name, c->k, w);
      result_row row = row_for(*c);
      if (adaptive) {
        std::string text;
        for (uint64_t n : level_rays[c->k]) text += (text.empty() ? "" : ";") + std::to_string(n);
        row.cells["level_rays"] = text;
      }
      const std::vector<double>& traces = trace_ms[c->k];
      row.cells["points_traced"] = std::to_string(points[c->k]), row.cells["rays"] = std::to_string(rays[c->k]);
      row.cells["rays_cast"] = std::to_string(cast[c->k]);
      row.cells["trace_ms"] = number(summarise(traces).median);
      row.cells["reconstruct_ms"] = number(summarise(reconstruct_ms[m]).median);
      std::vector<double> frame_ms = plus(traces, reconstruct_ms[m]);
      if (c->taa) frame_ms = plus(frame_ms, taa_ms[m]);
      const std::vector<double> full = c->taa ? plus(full_ms, full_taa_ms) : full_ms;
      const paired_timing paired = pair_timings(frame_ms, full);
      put_timing(row, paired, o_.spread_limit);
      row.cells["speedup_samples"] = samples_text(paired.ratios);
      row.cells["trace_cpu_ms"] = number(summarise(trace_cpu[c->k]).median);
      row.cells["reconstruct_cpu_ms"] = number(summarise(reconstruct_cpu[m]).median);
      row.cells["full_cpu_ms"] = number(summarise(full_cpu).median);
      put_errors(row, compare_images(image, *truth_, eye_, gp.at, o_.judging()));
      if (o_.temporal_frames >= 2 && !c->taa) {
        st_.say(fmt::format("temporal {} {} {} k={} spp={}", scene, what, method_name(c->how), c->k, spp));
        const flicker_params fp = temporal_path();
        const std::vector<frame> none;  // (both branches lvalues: the converged path is not copied)
        const flicker_report fl = measure_flicker(r_, gp.at, p, fp, o_.jod ? path_at(c->gaze).frames : none);
        row.cells["flicker"] = number(fl.raw);
        row.cells["flicker_taa"] = number(fl.taa);
        row.cells["flicker_reference"] = number(fl.reference);
        if (fl.has_jod) {
          const fvvdp_result* seq[] = {&fl.jod_raw, &fl.jod_taa, &fl.jod_full, &path_at(c->gaze).floor};
          const char* name[] = {"video_jod", "video_jod_taa", "video_jod_full", "noise_floor_video_jod"};
          for (int i = 0; i < 4; ++i)
            row.cells[name[i]] = number(seq[i]->jod), row.cells[std::string(name[i]) + "_nonfoveated"] = number(seq[i]->jod_nonfoveated);
        }
      }
      st_.finish(*c, row);
    }
  }

  // A reuse row: the set traced along the temporal path every point every frame and with
  // o_.reuse (measure_reuse), o_.frames timing passes, each pair beside a full-resolution
  // frame of the same pose. Its frame time per pair is the reusing trace's plus the method's
  // reconstruction as timed on the still view (reuse does not change that work); its errors
  // are those of the sequence (video JOD, flicker), not of a single frame.
  void measure_reuse_row(const config& c, render_params p, double reconstruct_ms) {
    p.reconstruct.how = c.how, p.reconstruct.k = c.k;
    p.taa = false;
    p.reuse = o_.reuse;
    const flicker_params fp = temporal_path();
    const std::vector<frame> none;  // (both branches lvalues: the converged path is not copied)
    const reuse_path_report rp =
        measure_reuse(r_, st_.gazes[c.gaze].at, p, fp, o_.jod ? path_at(c.gaze).frames : none, o_.frames, true);
    std::vector<double> traced, kept;
    for (const reuse_report& r : rp.reuse) traced.push_back(double(r.traced)), kept.push_back(r.reused_share());
    result_row row = row_for(c);
    const double rays = mean_after_first(rp.rays_reuse), cast = mean_after_first(rp.cast_reuse);
    row.cells["points_traced"] = std::to_string(std::llround(mean_after_first(traced)));
    row.cells["rays"] = std::to_string(std::llround(rays));
    row.cells["rays_cast"] = std::to_string(std::llround(cast));
    row.cells["reuse_kept"] = number(mean_after_first(kept));
    row.cells["reuse_rays_ratio"] = number(rays / mean_after_first(rp.rays_full));
    row.cells["reuse_rays_cast_ratio"] = number(cast / mean_after_first(rp.cast_full));
    std::vector<double> frame_ms;
    for (double trace_ms : rp.trace_ms_reuse) frame_ms.push_back(trace_ms + reconstruct_ms);
    const timing ratio = summarise(rp.trace_ratios());
    row.cells["reuse_trace_ratio"] = number(ratio.median);
    row.cells["reuse_trace_ratio_lo"] = number(ratio.min), row.cells["reuse_trace_ratio_hi"] = number(ratio.max);
    row.cells["trace_ms"] = number(summarise(rp.trace_ms_reuse).median);
    row.cells["reconstruct_ms"] = number(reconstruct_ms);
    const paired_timing paired = pair_timings(frame_ms, rp.trace_ms_full_resolution);
    put_timing(row, paired, o_.spread_limit);
    row.cells["speedup_samples"] = samples_text(paired.ratios);
    row.cells["flicker"] = number(rp.flicker_reuse), row.cells["reuse_flicker_traced"] = number(rp.flicker_full);
    if (rp.has_jod) {
      const fvvdp_result& floor = path_at(c.gaze).floor;
      row.cells["video_jod"] = number(rp.jod_reuse.jod), row.cells["video_jod_nonfoveated"] = number(rp.jod_reuse.jod_nonfoveated);
      row.cells["reuse_video_jod_traced"] = number(rp.jod_full.jod);
      row.cells["noise_floor_video_jod"] = number(floor.jod), row.cells["noise_floor_video_jod_nonfoveated"] = number(floor.jod_nonfoveated);
    }
    st_.finish(c, row);
  }

  flicker_params temporal_path() const {
    flicker_params fp;
    fp.frames = o_.temporal_frames, fp.fps = o_.temporal_fps, fp.photometry = o_.photometry;
    return fp;
  }

  // Converged frames along the temporal path from gaze g, and the noise floor of the video
  // JOD measured against them (a second path, the other seed): traced once per gaze.
  struct path_truth {
    std::vector<frame> frames;
    fvvdp_result floor;
  };
  const path_truth& path_at(size_t g) {
    if (!paths_.count(g)) {
      st_.say(fmt::format("converged temporal path at {} ({} frames, twice)", st_.gazes[g].name, o_.temporal_frames));
      const auto [seed_a, seed_b] = converged_seeds(o_.render.seed);
      path_truth t;
      t.frames = references_.path(r_, o_.render, o_.reference_spp, seed_a, temporal_path(), st_.sayer());
      t.floor = converged_path_floor(references_.path(r_, o_.render, o_.reference_spp, seed_b, temporal_path(), st_.sayer()),
                                     t.frames, st_.gazes[g].at, st_.display, temporal_path());
      paths_[g] = std::move(t);
    }
    return paths_[g];
  }

  sweep_state& st_;
  const bench_options& o_;
  size_t sc_;
  renderer r_;
  reference_cache references_;
  const spacing_model eye_;  // the eye errors are judged by: the thesis's acuity, at true eccentricity
  const frame* truth_ = nullptr;
  const frame* second_ = nullptr;
  std::map<size_t, comparison> floors_;
  std::map<size_t, path_truth> paths_;
  std::map<uint32_t, full_frame> fulls_;
  std::map<uint32_t, std::vector<double>> ladder_, ladder_taa_;
  taa_state full_history_;  // time_resolve's
};

}  // namespace

size_t run_bench(const bench_options& o, const bench_reporter& report) {
  sweep_state st{o, report, check_bench_options(o)};
  st.results_path = (fs::path(results_dir(o)) / "results.csv").string();
  require_output_dir("-o", o.out);
  st.gazes = parse_gazes(o.gazes, st.display, o.render.seed);
  st.done = resumed_keys(o, st.display, st.results_path);
  st.all = all_configs(o, st.gazes);
  if (o.shard_count > 1) {  // this shard's slice: every shard_count-th configuration
    std::vector<config> mine;
    for (size_t i = o.shard_index; i < st.all.size(); i += o.shard_count) mine.push_back(st.all[i]);
    st.all = std::move(mine);
  }
  for (const config& c : st.all) st.todo += !st.done.count(c.key);
  std::vector<std::shared_ptr<const scene>> scenes = load_needed_scenes(st);
  // Only now is anything written.
  report.line(fmt::format("{} configurations, {} already in {}, {} to measure", st.all.size(), st.all.size() - st.todo,
                          st.results_path, st.todo));
  if (const uint32_t kept = sweep_render(o).weight_caches; kept > cl_reconstructor::default_weight_caches) {
    double bytes = 0;  // each configuration's weights for one screen, on the host and the device
    for (uint32_t k : cached_weight_ks(o)) bytes += 2.0 * st.display.width * st.display.height * k * sizeof(float);
    report.line(fmt::format("keeping {} cached-weight configurations: about {:.1f} GiB of weights per gaze", kept, bytes / (1u << 30)));
  }
  make_output_dir((fs::path(o.out) / "references").string());
  make_output_dir(results_dir(o));
  for (size_t sc = 0; sc < o.scenes.size() && st.measured_rows < st.todo; ++sc) {
    if (!scenes[sc]) continue;
    scene_sweep sweep(st, sc, std::move(scenes[sc]));
    sweep.measure_sets(row_kind::foveated);
    sweep.measure_sets(row_kind::uniform);
    sweep.measure_falloff();
    sweep.measure_full();
  }
  st.say("done");
  return st.measured_rows;
}

std::string results_dir(const bench_options& o) {
  if (o.shard_count <= 1) return o.out;
  return (fs::path(o.out) / fmt::format("shard-{}-of-{}", o.shard_index, o.shard_count)).string();
}

void parse_shard(const std::string& text, bool given, bench_options& o) {
  auto whole = [](const std::string& s, long& v) {
    if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos) return false;
    v = std::stol(s);
    return true;
  };
  long index = 0, count = 1;
  if (given) {
    const size_t slash = text.find('/');
    if (slash == std::string::npos || !whole(text.substr(0, slash), index) || !whole(text.substr(slash + 1), count) || count < 1 ||
        index >= count)
      throw usage_error(fmt::format("--shard: '{}' is not I/N with 0 <= I < N (e.g. 0/4)", text));
  } else if (const char* n = std::getenv("SLURM_ARRAY_TASK_COUNT")) {
    const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
    const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
    long first = 0;
    if (!whole(n, count) || count < 1) throw usage_error(fmt::format("SLURM_ARRAY_TASK_COUNT '{}' is not a count", n));
    if (!id || !whole(id, index)) throw usage_error("SLURM_ARRAY_TASK_COUNT is set but SLURM_ARRAY_TASK_ID is not a task number");
    if (min && !whole(min, first)) throw usage_error(fmt::format("SLURM_ARRAY_TASK_MIN '{}' is not a task number", min));
    if (index < first || index - first >= count)
      throw usage_error(fmt::format("SLURM_ARRAY_TASK_ID {} lies outside the array's {} tasks from {} (an --array with "
                                    "a step? give --shard I/N)", index, count, first));
    index -= first;
  }
  o.shard_index = uint32_t(index), o.shard_count = uint32_t(count);
}

size_t merge_results(const merge_options& m, int argc, char** argv) {
  if (m.inputs.empty()) throw usage_error("merge: give the results.csv (or directories) to merge");
  if (m.out.empty()) throw usage_error("merge: -o is required");
  const std::string out_csv = (fs::path(m.out) / "results.csv").string();
  if (fs::exists(out_csv)) throw usage_error(fmt::format("-o {}: {} exists; merge into a new directory", m.out, out_csv));
  require_output_dir("-o", m.out);
  std::vector<result_row> rows;
  std::map<std::string, std::string> first_file;  // key -> the file it came from
  const char* same[] = {"display", "texture_footprint", "fovea", "acuity", "sampler", "render_settings", "reference_spp"};
  std::string first_path;
  for (const std::string& input : m.inputs) {
    const std::string path = fs::is_directory(input) ? (fs::path(input) / "results.csv").string() : input;
    if (fs::equivalent(fs::path(path).parent_path().empty() ? "." : fs::path(path).parent_path(), m.out))
      throw usage_error(fmt::format("-o {}: also an input; merge into a new directory", m.out));
    for (result_row& r : read_results(path)) {
      if (!rows.empty())
        for (const char* c : same)
          if (r.text(c) != rows.front().text(c))
            throw std::runtime_error(fmt::format("{}: its rows have {} {}, those of {} {}: not one sweep", path, c, r.text(c),
                                                 first_path, rows.front().text(c)));
      if (const auto [it, added] = first_file.emplace(r.key(), path); !added)
        throw std::runtime_error(fmt::format("{}: a configuration ({}) also in {}", path, r.key(), it->second));
      if (rows.empty()) first_path = path;
      rows.push_back(std::move(r));
    }
  }
  if (rows.empty()) throw std::runtime_error("merge: the inputs hold no rows");
  bench_options o;  // what the report reads, from the rows and merge's flags
  o.out = m.out, o.spread_limit = m.spread_limit, o.budget_psnr = m.budget_psnr, o.budget_foveated = m.budget_foveated;
  o.ks.clear();
  o.frames = 0;
  std::set<uint32_t> ks;
  for (const result_row& r : rows) {
    if (!r.text("k").empty()) ks.insert(uint32_t(r.number("k")));
    o.frames = std::max<uint32_t>(o.frames, uint32_t(r.number("frames")));
  }
  o.ks.assign(ks.begin(), ks.end());
  if (o.ks.empty()) o.ks = {1};
  o.reference_spp = uint32_t(rows.front().number("reference_spp"));
  make_output_dir(m.out);
  {
    results_writer writer(out_csv);
    for (const result_row& r : rows) writer.append(r);
  }
  for (const std::string& why : write_bench_figures(rows, o, m.out)) std::cerr << "fovbench: warning: " << why << "\n";
  write_bench_report(rows, o, (fs::path(m.out) / "report.md").string(), argc, argv);
  return rows.size();
}

}  // namespace fov
