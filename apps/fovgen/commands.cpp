#include "commands.h"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "../common/cli.h"
#include "fov/files.h"
#include "fov/nested.h"
#include "fov/pointset_io.h"
#include "plot.h"
#include "plots.h"

namespace fov {

namespace {
using json = nlohmann::json;
using clock_type = std::chrono::steady_clock;
}  // namespace

void add_generate_flags(CLI::App& app, generate_options& o) {
  app.add_option("--display", o.display, display_help() + "; --width, --height and -v given with it replace its own");
  app.add_option("--width", o.width, "Screen width W in pixels (canvas is 2W)");
  app.add_option("--height", o.height, "Screen height H in pixels (canvas is 2H)");
  app.add_option("--viewing-distance,-v", o.viewing_distance, "Viewing distance in display widths");
  app.add_option("--k", o.k, "Neighbours stored per canvas pixel, 1..32");
  app.add_option("--group", o.group, "Neighbour ranks per table plane group (layout; see docs)");
  app.add_option("--seed", o.seed, "Random seed; same flags + seed give a byte-identical file");
  app.add_option("--saturation", o.saturation, "Consecutive rejected darts that end a tile's dart throwing");
  app.add_option("--encoding", o.encoding,
                 "Neighbours on disk: ref-left-zstd (the table, compact), raw (the table, mmap-able) or cells (no table: "
                 "k-NN cells built from the points at load, memory that grows with the points; for large displays)");
  add_label_option(app, "--fovea", o.fovea, fovea_layout_labels,
                        "darts: Poisson-disc darts everywhere (the thesis); grid: one point per pixel centre "
                        "where the model's spacing is at most --grid-spacing, darts outside");
  app.add_option("--grid-spacing", o.grid_spacing,
                 "With --fovea grid: the largest model spacing (pixels, 0.5..4) that still gets grid points");
  add_label_option(app, "--acuity", o.acuity.model, acuity_model_labels,
                   "Acuity model behind the spacing (docs/schemes.md): csf, the thesis's contrast-sensitivity "
                   "cut-off; linear-mar, Guenter's linear MAR sampled as HVVR does; piecewise-mar, VaFR's");
  app.add_option("--mar-slope", o.acuity.mar_slope,
                 fmt::format("linear-mar: slope m of the MAR, degrees per degree, (0, {}] (default {}, HVVR's; "
                             "Guenter's m_A is 0.0275)", max_mar_slope, acuity_params{}.mar_slope));
  app.add_option("--mar-fovea", o.acuity.mar_fovea_deg,
                 fmt::format("linear-mar: foveal MAR w0 in degrees, {:.4g}..{} (default 1/60, HVVR's; Guenter's 1/48)",
                             min_mar_fovea_deg, max_mar_fovea_deg));
  app.add_option("--mar-dead-zone", o.acuity.mar_dead_zone_deg,
                 fmt::format("linear-mar: eccentricity in degrees held at w0 for eye-tracking error, 0..{} (default "
                             "{}, HVVR's)", max_mar_dead_zone_deg, acuity_params{}.mar_dead_zone_deg));
  app.add_option("--acuity-pivots", o.pivots,
                 fmt::format("piecewise-mar: the acuity in cycles per degree at 0,10,20,30,60 degrees, each {}..{} "
                             "and none above the one before (default 40,10,6,5,4, VaFR's)", min_pivot_cpd, max_pivot_cpd))
      ->delimiter(',')
      ->expected(5);
  add_label_option(app, "--sampler", o.sampler, point_sampler_labels,
                   "What places the points (docs/schemes.md): poisson, darts at the model's spacing (the thesis); "
                   "polar, rings a pitch apart (HVVR's pattern); log-polar, VaFR's lattice");
  app.add_flag("--json", o.json, "Print a JSON summary on stdout");
}

void note_given_flags(const CLI::App& app, generate_options& o) {
  o.width_given = app.count("--width") > 0, o.height_given = app.count("--height") > 0;
  o.distance_given = app.count("--viewing-distance") > 0, o.grid_spacing_given = app.count("--grid-spacing") > 0;
  o.mar_given = app.count("--mar-slope") + app.count("--mar-fovea") + app.count("--mar-dead-zone") > 0;
}

namespace {

// The acuity model with its parameters; flags of another model's parameters, or values out
// of their documented ranges, are usage errors naming the flag.
acuity_params acuity_from_flags(const generate_options& o) {
  acuity_params a = o.acuity;
  const bool linear = a.model == acuity_model::linear_mar, piecewise = a.model == acuity_model::piecewise_mar;
  if (o.mar_given && !linear) throw usage_error("--mar-slope, --mar-fovea and --mar-dead-zone need --acuity linear-mar");
  if (!o.pivots.empty() && !piecewise) throw usage_error("--acuity-pivots needs --acuity piecewise-mar");
  if (!(a.mar_slope > 0 && a.mar_slope <= max_mar_slope))
    throw usage_error(fmt::format("--mar-slope must lie in (0, {}] (got {})", max_mar_slope, a.mar_slope));
  if (!(a.mar_fovea_deg >= min_mar_fovea_deg && a.mar_fovea_deg <= max_mar_fovea_deg))
    throw usage_error(fmt::format("--mar-fovea must lie in {:.4g}..{} degrees (got {})", min_mar_fovea_deg,
                                  max_mar_fovea_deg, a.mar_fovea_deg));
  if (!(a.mar_dead_zone_deg >= 0 && a.mar_dead_zone_deg <= max_mar_dead_zone_deg))
    throw usage_error(fmt::format("--mar-dead-zone must lie in 0..{} degrees (got {})", max_mar_dead_zone_deg,
                                  a.mar_dead_zone_deg));
  if (!o.pivots.empty()) {
    if (o.pivots.size() != std::size(a.pivot_cpd)) throw usage_error("--acuity-pivots takes 5 values");
    std::copy(o.pivots.begin(), o.pivots.end(), a.pivot_cpd);
  }
  spacing_model check;
  check.acuity = a;
  if (const std::string why = validate(check); !why.empty())
    throw usage_error(std::string(piecewise ? "--acuity-pivots: " : "--acuity: ") + why);
  return a;
}

spacing_model model_from(const generate_options& o) {
  spacing_model m;
  if (!o.display.empty()) m.display = require_display("--display", o.display);
  if (o.display.empty() || o.width_given) m.display.width = o.width;
  if (o.display.empty() || o.height_given) m.display.height = o.height;
  if (o.display.empty() || o.distance_given) m.display.viewing_distance = o.viewing_distance;
  m.scale = o.scale;
  m.acuity = acuity_from_flags(o);
  if (o.width <= 0 && o.width_given) throw usage_error(fmt::format("--width must be positive (got {})", o.width));
  if (o.height <= 0 && o.height_given) throw usage_error(fmt::format("--height must be positive (got {})", o.height));
  if (const std::string why = viewing_distance_problem(m.display.viewing_distance); !why.empty())
    throw usage_error("--viewing-distance: " + why);
  if (!(o.scale > 0) || !std::isfinite(o.scale))
    throw usage_error(fmt::format("--scale must be positive (got {})", o.scale));
  if (o.k < 1 || o.k > max_knn) throw usage_error(fmt::format("--k must lie in 1..{} (got {})", max_knn, o.k));
  if (o.group < 1) throw usage_error("--group must be at least 1");
  if (o.saturation < 1) throw usage_error("--saturation must be at least 1");
  if (!valid_grid_spacing(o.grid_spacing))
    throw usage_error(fmt::format("--grid-spacing must lie in {}..{} pixels (got {})", min_grid_spacing,
                                  max_grid_spacing, o.grid_spacing));
  if (o.grid_spacing_given && o.fovea != fovea_layout::grid)
    throw usage_error("--grid-spacing needs --fovea grid");
  table_encoding e;
  if (!parse_table_encoding(o.encoding, e))
    throw usage_error(fmt::format("--encoding: unknown '{}' (ref-left-zstd, raw, cells)", o.encoding));
  if (const std::string why = validate(m); !why.empty()) throw usage_error(why);
  if (o.sampler != point_sampler::poisson && o.fovea != fovea_layout::darts)
    throw usage_error("--fovea grid needs --sampler poisson (a lattice has its own fovea)");
  if (o.sampler != point_sampler::poisson && !o.levels.empty())
    throw usage_error("--levels needs --sampler poisson (a nested set is darts)");
  if (!o.levels.empty()) {
    if (const std::string why = levels_problem(o.levels); !why.empty()) throw usage_error(why);
    if (o.scale_given) throw usage_error("--scale and --levels: a nested set's scales are its levels");
    if (o.fovea != fovea_layout::darts) throw usage_error("--levels needs --fovea darts (a nested set has no grid fovea)");
    for (double s : o.levels) {
      spacing_model level = m;
      level.scale = s;
      if (const std::string why = validate(level); !why.empty()) throw usage_error(fmt::format("--levels {}: {}", s, why));
    }
  }
  if (e != table_encoding::cells)
    if (const std::string why = knn_table_memory_problem(m.display, o.k); !why.empty())
      throw usage_error("--display: " + why + "; --encoding cells keeps neighbours in memory that grows with the points");
  return m;
}

// The model's own parameters, named as its flags are.
json acuity_json(const acuity_params& a) {
  switch (a.model) {
    case acuity_model::wang_csf: return {{"ct0", a.ct0}, {"alpha", a.alpha}, {"e2", a.e2}};
    case acuity_model::linear_mar:
      return {{"mar_slope", a.mar_slope}, {"mar_fovea_deg", a.mar_fovea_deg}, {"mar_dead_zone_deg", a.mar_dead_zone_deg}};
    case acuity_model::piecewise_mar: {
      json pivots = json::array();
      for (size_t i = 0; i < std::size(a.pivot_cpd); ++i)
        pivots.push_back({{"eccentricity_deg", piecewise_pivots_deg[i]}, {"cpd", a.pivot_cpd[i]}});
      return {{"pivots", pivots}};
    }
  }
  return json::object();
}

json summary(const pointset& set, const std::string& path) {
  json j;
  j["file"] = path;
  j["width"] = set.model.display.width;
  j["height"] = set.model.display.height;
  j["viewing_distance"] = set.model.display.viewing_distance;
  j["display"] = display_name(set.model.display);
  j["pixels_per_degree"] = pixels_per_degree(set.model.display);
  j["fov_deg"] = {horizontal_fov_deg(set.model.display), vertical_fov_deg(set.model.display)};
  j["scale"] = set.model.scale;
  if (set.nested()) {
    // Per level (0 the coarsest): its scale, the points of its set (levels 0..l) and its own.
    std::vector<uint64_t> own(set.level_count(), 0);
    for (uint8_t l : set.level) ++own[l];
    json levels = json::array();
    uint64_t cumulative = 0;
    for (uint32_t l = 0; l < set.level_count(); ++l) {
      cumulative += own[l];
      levels.push_back({{"level", l}, {"scale", set.level_scales[l]}, {"points", cumulative}, {"new_points", own[l]}});
    }
    j["levels"] = levels;
  }
  j["acuity"] = acuity_model_name(set.model.acuity.model);
  j["acuity_params"] = acuity_json(set.model.acuity);
  j["sampler"] = label_of(point_sampler_labels, set.darts.sampler);
  j["k"] = stored_k(set);
  j["neighbours"] = label_of(knn_storage_labels, set.storage());
  if (set.table.k != 0) j["table_group"] = set.table.group;
  // Bytes the neighbours take in memory once loaded (the table's entries, or the cells').
  if (set.table.k != 0 && !set.table.entries.empty()) j["knn_memory_bytes"] = set.table.entries.size() * 4;
  if (set.cells.loaded()) j["knn_memory_bytes"] = set.cells.bytes();
  j["seed"] = set.darts.seed;
  j["saturation_rejections"] = set.darts.saturation_rejections;
  j["fovea"] = label_of(fovea_layout_labels, set.darts.fovea);
  if (set.darts.fovea == fovea_layout::grid) j["grid_spacing"] = set.darts.grid_spacing;
  j["points_total"] = set.points.size();
  j["grid_points"] = set.stats.grid_points;
  j["phase1_points"] = set.stats.phase1_points;
  j["phase2_points"] = set.stats.phase2_points;
  j["darts_thrown"] = set.stats.darts_thrown;
  j["free_fraction"] = set.stats.free_fraction;
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (!ec) j["file_bytes"] = bytes;
  return j;
}

// Pairs closer than the spacing rule allows: in the whole set, and (nested) in each level's set.
// The rule is the darts': a lattice keeps its pitch only on average (null).
void add_spacing_violations(json& j, const pointset& set) {
  if (set.darts.sampler != point_sampler::poisson) {
    j["spacing_violations"] = nullptr;
    return;
  }
  j["spacing_violations"] = count_spacing_violations(set.points, set.canvas_width(), set.canvas_height());
  if (!set.nested()) return;
  for (uint32_t l = 0; l < set.level_count(); ++l)
    j["levels"][l]["spacing_violations"] = count_spacing_violations(level_points(set, l), set.canvas_width(), set.canvas_height());
}

// Wall-clock provenance lives beside the set, so the set itself stays byte-identical.
std::string provenance_path(const std::string& set_path) { return set_path + ".gen.json"; }

void add_timings(json& j, const pointset& set) {
  j["dart_seconds"] = set.stats.seconds;
  j["knn_seconds"] = set.knn_seconds;
  j["generation_seconds"] = set.stats.seconds + set.knn_seconds;
}

void write_provenance(const pointset& set, const std::string& path) {
  json j;
  add_timings(j, set);
  j["threads"] = std::thread::hardware_concurrency();
  j["command"] = "fovgen";
  const std::string text = j.dump(2) + "\n";
  write_file_atomic(provenance_path(path), text.data(), text.size());
}

// Timings from the provenance file, or nulls when it is missing or unreadable.
void read_timings(json& j, const std::string& set_path) {
  j["generation_seconds"] = nullptr;
  // The sidecar is optional: one that is not a small regular file is passed over.
  const std::string sidecar = provenance_path(set_path);
  std::string text;
  try {
    text = read_input_file(sidecar, 1u << 20, "provenance file");
  } catch (const file_error&) {
    return;
  }
  const json p = json::parse(text, nullptr, false);
  if (p.is_discarded()) return;
  for (const char* key : {"dart_seconds", "knn_seconds", "generation_seconds"})
    if (p.contains(key) && p[key].is_number()) j[key] = p[key];
}

// Generates one set and writes it; the table goes to disk band by band.
pointset generate_file(const spacing_model& model, const generate_options& o, const std::string& path) {
  dart_params darts;
  darts.sampler = o.sampler;
  darts.seed = o.seed;
  darts.saturation_rejections = o.saturation;
  darts.fovea = o.fovea;
  darts.grid_spacing = o.grid_spacing;
  pointset set;
  if (!o.levels.empty()) {
    set = throw_nested_pointset(model, o.levels, darts);  // (--levels checked by parse)
    if (const uint64_t coarsest = coarsest_level_points(set); coarsest < o.k)
      throw usage_error(fmt::format("--k {} exceeds the {} points of the coarsest level; use --k {} or less", o.k,
                                    coarsest, coarsest));
  } else {
    set.model = model;
    set.darts = darts;
    set.points = place_points(model, set.darts, &set.stats);
  }
  if (set.points.size() < o.k)
    throw usage_error(fmt::format("--k {} exceeds the {} points of this set; use --k {} or less", o.k,
                                  set.points.size(), set.points.size()));
  const auto start = clock_type::now();
  save_params save;
  parse_table_encoding(o.encoding, save.encoding);
  if (save.encoding == table_encoding::cells) {
    knn_params kp;
    kp.k = o.k;
    try {
      build_neighbours(set, kp, knn_storage::cells);
    } catch (const std::invalid_argument& e) {
      throw usage_error(std::string("--display: ") + e.what());
    }
    set.knn_seconds = std::chrono::duration<double>(clock_type::now() - start).count();
    save_pointset(path, set, save);
    write_provenance(set, path);
    return set;
  }
  knn_builder builder(set.points, set.canvas_width(), set.canvas_height(), o.k);
  save_pointset(
      path, set, o.k, o.group,
      [&](uint32_t y0, uint32_t y1, uint32_t* out) {
        builder.rows(y0, y1, out);
        set.knn_seconds = std::chrono::duration<double>(clock_type::now() - start).count();
      },
      save);
  write_provenance(set, path);
  set.table.k = o.k;
  set.table.group = std::clamp<uint32_t>(o.group, 1, o.k);
  return set;
}

std::vector<double> parse_scales(const std::string& text) {
  std::vector<double> out;
  const auto colon = text.find(':');
  auto number = [&](const std::string& s) {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0' || !(v > 0)) throw usage_error(fmt::format("--scales: bad number '{}'", s));
    return v;
  };
  if (colon != std::string::npos) {
    const auto colon2 = text.find(':', colon + 1);
    if (colon2 == std::string::npos) throw usage_error("--scales: expected START:END:STEP or a comma list");
    const double a = number(text.substr(0, colon)), b = number(text.substr(colon + 1, colon2 - colon - 1));
    const double step = number(text.substr(colon2 + 1));
    if (b < a) throw usage_error("--scales: END is below START");
    const long n = std::lround(std::floor((b - a) / step + 1e-6));
    if (n > 1000) throw usage_error("--scales: more than 1000 values");
    for (long i = 0; i <= n; ++i) out.push_back(std::round((a + i * step) * 1e9) / 1e9);
  } else {
    size_t at = 0;
    while (at <= text.size()) {
      const auto comma = text.find(',', at);
      out.push_back(number(text.substr(at, comma == std::string::npos ? std::string::npos : comma - at)));
      if (comma == std::string::npos) break;
      at = comma + 1;
    }
  }
  return out;
}

std::string format_duration(double seconds) {
  const long s = std::lround(seconds);
  return s >= 60 ? fmt::format("{}m{:02}s", s / 60, s % 60) : fmt::format("{}s", s);
}

void progress(size_t done, size_t total, double elapsed, const std::string& label) {
  const int width = 30;
  const int filled = int(width * done / std::max<size_t>(1, total));
  const std::string eta = done ? format_duration(elapsed / done * (total - done)) : "?";
  if (!isatty(fileno(stderr))) {  // a log, not a terminal: a plain line per set, no bar
    fmt::print(stderr, "fovgen: {}/{} {}, elapsed {}\n", done, total, label, format_duration(elapsed));
    return;
  }
  fmt::print(stderr, "\r[{}{}] {}/{} {} elapsed {} ETA {}", std::string(filled, '#'), std::string(width - filled, ' '), done,
             total, label, format_duration(elapsed), eta);
  if (done == total) fmt::print(stderr, "\n");
}

}  // namespace

int run_generate(const generate_options& o) {
  const std::string& output = o.output;
  if (output.empty()) throw usage_error("-o: an output file is required");
  const spacing_model model = model_from(o);
  require_output("-o", output);  // fail before minutes of work, as a usage error
  const pointset set = generate_file(model, o, output);
  json j = summary(set, output);
  add_timings(j, set);
  add_spacing_violations(j, set);
  if (o.json) {
    std::cout << j.dump(2) << "\n";
  } else if (set.darts.sampler != point_sampler::poisson) {
    fmt::print("{}: {} points placed by the {} lattice in {:.1f} s + {} {:.1f} s, {:.1f} MB\n", output, set.points.size(),
               label_of(point_sampler_labels, set.darts.sampler), set.stats.seconds, label_of(knn_storage_labels, set.storage()),
               set.knn_seconds, j.value("file_bytes", 0.0) / 1e6);
  } else {
    fmt::print("{}: {} points ({} on the foveal grid, {} + {} darts in phase 2), free area {:.2e}, {} spacing violations, "
               "darts {:.1f} s + {} {:.1f} s, {:.1f} MB\n",
               output, set.points.size(), set.stats.grid_points, set.stats.phase1_points, set.stats.phase2_points, set.stats.free_fraction,
               j["spacing_violations"].get<uint64_t>(), set.stats.seconds, label_of(knn_storage_labels, set.storage()), set.knn_seconds,
               j.value("file_bytes", 0.0) / 1e6);
  }
  return 0;
}

int run_info(const info_options& o) {
  const std::string &file = o.file, &gaze_text = o.gaze;
  const uint32_t k_used = o.k;
  const bool as_json = o.json;
  const pointset set = load_pointset(file);  // the whole file, table too: info vouches for it
  if (k_used > stored_k(set))
    throw usage_error(fmt::format("--k {}: {} stores {} neighbours per pixel", k_used, file, stored_k(set)));
  json j = summary(set, file);
  read_timings(j, file);
  add_spacing_violations(j, set);
  if (!gaze_text.empty()) {
    const gaze_point gaze = require_gaze("--gaze", gaze_text, set.model.display);
    const uint32_t k = k_used ? std::min(k_used, stored_k(set)) : stored_k(set);
    const traced_set t = count_traced_points(set, gaze, k);
    j["gaze"] = {gaze.x, gaze.y};
    j["k_used"] = k;
    j["points_on_screen"] = t.on_screen;
    j["points_referenced_off_screen"] = t.referenced_off_screen;
    j["points_traced"] = t.total();
    // The farthest k-th neighbour of any canvas pixel (with cells: a bound on it).
    j["knn_max_radius"] = set.table.k != 0 ? set.table.max_radius : set.cells.max_radius;
    j["traced_fraction"] = double(t.total()) / double(set.points.size());
    // The thesis's rule for comparison: on-screen points plus a fixed 10-pixel margin.
    const canvas_offset o = offset_for_gaze(set.model.display, gaze);
    const int w = set.model.display.width, h = set.model.display.height;
    uint64_t margin10 = 0;
    for (const point& p : set.points)
      margin10 += p.x >= o.x - 10 && p.x < o.x + w + 10 && p.y >= o.y - 10 && p.y < o.y + h + 10;
    j["points_thesis_margin10"] = margin10;
  }
  if (as_json) {
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  for (auto& [key, value] : j.items()) fmt::print("{:>30}: {}\n", key, value.dump());
  return 0;
}


int run_plot(const plot_options& o) {
  const std::string &plot_file = o.file, &plot_out = o.output, &plot_gaze = o.gaze;
  const uint32_t plot_k = o.k;
  const pointset set = load_pointset(plot_file);  // checked whole, as info does
  if (plot_k > stored_k(set))
    throw usage_error(fmt::format("--k {}: {} stores {} neighbours per pixel", plot_k, plot_file, stored_k(set)));
  std::optional<gaze_point> gaze;
  if (!plot_gaze.empty()) gaze = require_gaze("--gaze", plot_gaze, set.model.display);
  require_output("-o", plot_out, {plot_file});
  plot_points(set, plot_out, gaze, plot_k ? plot_k : stored_k(set));
  return 0;
}

int run_sweep(const sweep_options& o) {
  const generate_options& sweep_gen = o.generate;
  const std::string &sweep_scales = o.scales, &sweep_dir = o.dir;
  const bool skip_existing = o.skip_existing;
  const spacing_model base = model_from(sweep_gen);
  const std::vector<double> scales = parse_scales(sweep_scales);
  require_output_dir("-o", sweep_dir);
  make_output_dir(sweep_dir);
  plot_panel counts;
  counts.title = "Points in the set against scale s", counts.x_label = "scale factor s", counts.y_label = "points";
  for (const char* name : {"total", "traced, centred gaze", "traced, corner gaze"}) {
    plot_series s;
    s.name = s.scheme = name;
    counts.series.push_back(s);
  }
  std::string csv = "scale,points_total,points_traced_centre,points_traced_corner,free_fraction,generation_seconds,file_bytes\n";
  const auto start = clock_type::now();
  for (size_t i = 0; i < scales.size(); ++i) {
    const double s = scales[i];
    dart_params layout;
    layout.fovea = sweep_gen.fovea, layout.grid_spacing = sweep_gen.grid_spacing, layout.sampler = sweep_gen.sampler;
    spacing_model m = base;
    m.scale = s;
    const std::string path = (std::filesystem::path(sweep_dir) / pointset_file_name(m, layout)).string();
    progress(i, scales.size(), std::chrono::duration<double>(clock_type::now() - start).count(),
             fmt::format("s={:.2f}", s));
    if (const std::string why = validate(m); !why.empty()) throw usage_error(fmt::format("scale {}: {}", s, why));
    bool reuse = false;
    if (skip_existing && std::filesystem::exists(path)) {
      try {
        load_params lp;
        lp.table = false;
        const pointset old = load_pointset(path, lp);
        // Reuse only a set these exact flags would write again (the file is deterministic).
        reuse = old.model.scale == s && old.darts.seed == sweep_gen.seed &&
                old.darts.saturation_rejections == sweep_gen.saturation && stored_k(old) == sweep_gen.k &&
                fovea_label(old.darts) == fovea_label(layout) && old.darts.sampler == layout.sampler &&
                same_acuity(old.model.acuity, m.acuity) && (old.table.k == 0) == (sweep_gen.encoding == "cells") &&
                (old.table.k == 0 || old.table.group == std::clamp<uint32_t>(sweep_gen.group, 1, sweep_gen.k)) &&
                old.model.display.width == m.display.width && old.model.display.height == m.display.height &&
                old.model.display.viewing_distance == m.display.viewing_distance;
      } catch (const file_error&) {
      }
    }
    double gen_seconds = NAN;
    if (!reuse) {
      const pointset made = generate_file(m, sweep_gen, path);
      gen_seconds = made.stats.seconds + made.knn_seconds;
    }
    const pointset set = load_pointset(path);
    const traced_set centre = count_traced_points(set, screen_centre(m.display), stored_k(set));
    const traced_set corner = count_traced_points(set, {double(m.display.width), double(m.display.height)}, stored_k(set));
    counts.series[0].x.push_back(s), counts.series[0].y.push_back(double(set.points.size()));
    counts.series[1].x.push_back(s), counts.series[1].y.push_back(double(centre.total()));
    counts.series[2].x.push_back(s), counts.series[2].y.push_back(double(corner.total()));
    csv += fmt::format("{:.2f},{},{},{},{:.3e},{:.2f},{}\n", s, set.points.size(), centre.total(), corner.total(),
                       set.stats.free_fraction, gen_seconds,
                       std::filesystem::file_size(path));
  }
  progress(scales.size(), scales.size(), std::chrono::duration<double>(clock_type::now() - start).count(), "done");
  write_file_atomic(sweep_dir + "/point-counts.csv", csv.data(), csv.size());
  if (const std::string why = write_plot({counts}, sweep_dir + "/point-counts"); !why.empty())
    std::cerr << "fovgen: warning: " << why << "\n";
  std::cout << csv;
  return 0;
}

int run_displays(const std::string& spec, bool as_json) {
  std::vector<std::pair<display_geometry, std::string>> rows;  // geometry, what
  if (!spec.empty()) rows.emplace_back(require_display("--display", spec), "");
  else
    for (const display_preset_info& p : display_presets()) rows.emplace_back(p.geometry(), p.what);
  json all = json::array();
  std::string table =
      "| display | W x H | v (widths) | pixels per degree | field of view (deg) | what |\n|---|---|---|---|---|---|\n";
  for (const auto& [d, what] : rows) {
    all.push_back({{"display", display_name(d)}, {"width", d.width}, {"height", d.height},
                   {"viewing_distance", d.viewing_distance}, {"pixels_per_degree", pixels_per_degree(d)},
                   {"fov_deg", {horizontal_fov_deg(d), vertical_fov_deg(d)}}, {"what", what}});
    table += fmt::format("| `{}` | {} x {} | {:.4g} | {:.1f} | {:.1f} x {:.1f} | {} |\n", display_name(d), d.width, d.height,
                         d.viewing_distance, pixels_per_degree(d), horizontal_fov_deg(d), vertical_fov_deg(d), what);
  }
  std::cout << (as_json ? all.dump(2) + "\n" : table);
  return 0;
}

int run_acuity(const acuity_options& o) {
  spacing_model base;
  base.display = require_display("--display", o.display);
  if (!(o.scale > 0) || !std::isfinite(o.scale))
    throw usage_error(fmt::format("--scale must be positive (got {})", o.scale));
  base.scale = o.scale;
  if (const std::string why = validate(base); !why.empty()) throw usage_error(why);
  // From the gaze to the canvas corner, the farthest any point lies.
  const double corner = std::hypot(double(base.display.width), double(base.display.height));
  constexpr int steps = 400;
  const double fd = display_nyquist_cpd(base.display);
  plot_panel spacing, cutoff;
  spacing.title = "Point spacing against eccentricity (" + display_name(base.display) + ")";
  spacing.x_label = cutoff.x_label = "eccentricity (deg)";
  spacing.y_label = "minimum spacing p (px)";
  cutoff.title = "Cut-off frequency against eccentricity", cutoff.y_label = "cycles per degree";
  cutoff.log_y = true;
  std::string csv = "acuity,distance_px,eccentricity_deg,cutoff_cpd,spacing_px\n";
  json rows = json::array();
  for (const auto& [label, model] : acuity_model_labels) {
    spacing_model m = base;
    m.acuity.model = model;
    if (const std::string why = validate(m); !why.empty()) throw usage_error(fmt::format("--acuity {}: {}", label, why));
    plot_series ps;
    ps.name = ps.scheme = label;
    ps.markers = false;
    plot_series pc = ps;
    for (int i = 0; i <= steps; ++i) {
      const double d = corner * i / steps, e = eccentricity_deg(m, d);
      const double fc = cutoff_frequency_cpd(m.acuity, e), p = point_spacing_px(m, d);
      ps.x.push_back(e), ps.y.push_back(p), pc.x.push_back(e), pc.y.push_back(fc);
      csv += fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g}\n", label, d, e, fc, p);
      rows.push_back({{"acuity", label}, {"distance_px", d}, {"eccentricity_deg", e}, {"cutoff_cpd", fc}, {"spacing_px", p}});
    }
    spacing.series.push_back(ps), cutoff.series.push_back(pc);
  }
  plot_series nyquist;
  nyquist.name = "display Nyquist", nyquist.scheme = "full", nyquist.style = "dashed";
  nyquist.markers = false;
  nyquist.x = {0, spacing.series[0].x.back()}, nyquist.y = {fd, fd};
  cutoff.series.push_back(nyquist);
  if (!o.output.empty())
    if (const std::string why = write_plot({spacing, cutoff}, o.output); !why.empty())
      std::cerr << "fovgen: no figure: " << why << "\n";
  std::cout << (o.json ? json{{"display", display_name(base.display)}, {"scale", o.scale}, {"nyquist_cpd", fd}, {"rows", rows}}.dump(2) + "\n"
                       : csv);
  return 0;
}

}  // namespace fov
