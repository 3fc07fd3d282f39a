#include "sweep.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "fov/dart_throwing.h"
#include "fov/files.h"
#include "fov/reconstruct_params.h"
#include "fov/renderer.h"

namespace fov {

const std::vector<std::string>& result_columns() {
  static const std::vector<std::string> columns = {
      // What the row is.
      "scene", "gaze", "gaze_x", "gaze_y", "kind", "scale", "pixel_fraction", "method", "k", "ray_floor", "spp", "texture_footprint", "fovea",
      "display", "ppd",
      // The foveated sets' acuity model and sampler (fovgen --acuity, --sampler; issue 27).
      "acuity", "sampler",
      // Empty for a single frame; else the steady state after this many frames of TAA with a
      // still view, the rays in this pattern (--taa-frames, --pattern).
      "taa_frames", "taa_pattern",
      // A foveated row's density (issue 26): fixed (one set at `scale`) or adaptive (a nested
      // set of these level scales, refined per frame at this threshold; `scale` empty), and
      // an adaptive frame's rays per level, coarsest first.
      "density", "adaptive_threshold", "levels", "level_rays",
      // How a ray's colour is found (--integrator: direct or path) and, for path, the bounces
      // after the first hit (issue 29): the cost of a sample.
      "integrator", "bounces",
      // What it cost, timed interleaved with a full-resolution frame at the same spp: points
      // traced, camera rays, every ray cast (camera, shadow and bounce rays: what a sample
      // costs under the row's integrator), the full-resolution frame's camera rays.
      "points_traced", "rays", "rays_cast", "full_rays", "trace_ms", "reconstruct_ms", "frame_ms", "frame_ms_lo", "frame_ms_hi",
      "full_ms", "full_ms_lo", "full_ms_hi", "speedup", "speedup_lo", "speedup_hi", "timing_flag",
      // Per repetition: full / frame (paired), and on full rows the ladder (this spp's time
      // over the lowest spp's, timed back to back); process CPU time per stage (medians).
      "speedup_samples", "ladder_samples", "trace_cpu_ms", "reconstruct_cpu_ms", "full_cpu_ms",
      // Its error against the converged reference.
      "psnr", "ssim", "psnr_fovea", "ssim_fovea", "psnr_5_10", "ssim_5_10", "psnr_10_20", "ssim_10_20", "psnr_20_30",
      "ssim_20_30", "psnr_periphery", "ssim_periphery", "foveated_error", "foveated_psnr", "flip", "flip_fovea",
      "flip_5_10", "flip_10_20", "flip_20_30", "flip_periphery", "flip_p99", "foveated_flip", "foveated_flip_p99",
      "foveated_flip_worst_band", "jod", "jod_nonfoveated",
      // The converged reference's own error (a second one, another seed, against it) and
      // the share of each band's pixels that hit geometry.
      "reference_spp", "noise_floor_psnr", "noise_floor_psnr_fovea", "noise_floor_foveated_error", "noise_floor_flip",
      "noise_floor_flip_fovea", "noise_floor_foveated_flip", "noise_floor_jod", "noise_floor_jod_nonfoveated", "geometry_fovea", "geometry_5_10", "geometry_10_20",
      "geometry_20_30", "geometry_periphery",
      "flicker", "flicker_taa", "flicker_reference",
      // Video JOD along the temporal path against converged frames, gaze per frame: the
      // foveated frames raw and with TAA, full resolution at the row's spp, and the
      // converged path's own floor (a second one, another seed).
      "video_jod", "video_jod_nonfoveated", "video_jod_taa", "video_jod_taa_nonfoveated", "video_jod_full",
      "video_jod_full_nonfoveated", "noise_floor_video_jod", "noise_floor_video_jod_nonfoveated",
      // A reuse row (issue 28; docs/reuse.md): `reuse` temporal and its settings. Its set is
      // traced along the temporal path twice, every point every frame and reusing, over the
      // frames after the first: the share of points that kept a sample, its camera rays and
      // every ray against the full traces', the paired trace times' ratio (median, min, max),
      // and the fully traced sequence's video JOD and flicker (the row's own are reuse's).
      "reuse", "reuse_settings", "reuse_kept", "reuse_rays_ratio", "reuse_rays_cast_ratio", "reuse_trace_ratio",
      "reuse_trace_ratio_lo", "reuse_trace_ratio_hi", "reuse_video_jod_traced", "reuse_flicker_traced",
      "error_profile", "device", "neighbours", "frames", "render_settings"};
  return columns;
}

const std::set<std::string>& reuse_result_columns() {
  static const std::set<std::string> columns = [] {
    std::set<std::string> out;
    for (const std::string& c : result_columns())
      if (c.rfind("reuse", 0) == 0) out.insert(c);
    return out;
  }();
  return columns;
}

std::string result_row::key() const {
  return fmt::format("{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", text("scene"), text("gaze"), text("kind"), text("scale"),
                     text("pixel_fraction"), text("method"), text("k"), text("ray_floor"), text("spp"), text("taa_frames"),
                     text("taa_pattern"), text("density"), text("adaptive_threshold"), text("levels"), text("reuse"),
                     text("reuse_settings"));
}

const std::string& result_row::text(const std::string& column) const {
  static const std::string empty;
  const auto it = cells.find(column);
  return it == cells.end() ? empty : it->second;
}

row_kind result_row::kind() const {
  row_kind k{};
  if (!parse_label(row_kind_labels, text("kind"), k)) throw std::logic_error("a results row of no kind: " + printable(text("kind")));
  return k;
}

double result_row::number(const std::string& column) const {
  const std::string& t = text(column);
  if (t == "inf") return std::numeric_limits<double>::infinity();
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  return t.empty() || *end ? std::numeric_limits<double>::quiet_NaN() : v;
}

std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else cells.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

}  // namespace

std::string result_row_problem(const result_row& row) {
  row_kind kind{};
  if (!parse_label(row_kind_labels, row.text("kind"), kind))
    return fmt::format("kind '{}' is not {}", printable(row.text("kind")), label_alternatives(row_kind_labels));
  const std::string& how = row.text("method");
  method m{};
  if (kind == row_kind::full ? how != "full" : kind == row_kind::falloff ? how != "falloff" : !parse_label(method_labels, how, m))
    return fmt::format("method '{}' is not one a {} row has", printable(how), row_kind_name(kind));
  // A steady-state row names its frames (a whole number 2..max_taa_frames) and its pattern;
  // a single frame neither.
  const std::string& taa = row.text("taa_frames");
  const std::string& pattern = row.text("taa_pattern");
  if (!taa.empty()) {
    const double n = row.number("taa_frames");
    if (!(n >= 2 && n <= max_taa_frames && n == std::floor(n)))
      return fmt::format("taa_frames '{}' is not a whole number in 2..{}", printable(taa), max_taa_frames);
    ray_pattern rp{};
    if (!parse_label(ray_pattern_labels, pattern, rp))
      return fmt::format("taa_pattern '{}' is not {}", printable(pattern), label_alternatives(ray_pattern_labels));
  } else if (!pattern.empty()) {
    return fmt::format("taa_pattern '{}' without taa_frames", printable(pattern));
  }
  acuity_model acuity{};
  if (!parse_label(acuity_model_labels, row.text("acuity"), acuity))
    return fmt::format("acuity '{}' is not {}", printable(row.text("acuity")), label_alternatives(acuity_model_labels));
  point_sampler sampler{};
  if (!parse_label(point_sampler_labels, row.text("sampler"), sampler))
    return fmt::format("sampler '{}' is not {}", printable(row.text("sampler")), label_alternatives(point_sampler_labels));
  // The integrator (empty in rows from before its column: direct); bounces only with path.
  const std::string& how_traced = row.text("integrator");
  integrator traced{};
  if (!how_traced.empty() && !parse_label(integrator_labels, how_traced, traced))
    return fmt::format("integrator '{}' is not {}", printable(how_traced), label_alternatives(integrator_labels));
  const std::string& bounces = row.text("bounces");
  if (bounces.empty() != (how_traced != "path")) return "a path row names its bounces; no other row does";
  if (!bounces.empty()) {
    const double n = row.number("bounces");
    if (!(n >= 0 && n <= max_bounces && n == std::floor(n)))
      return fmt::format("bounces '{}' is not a whole number in 0..{}", printable(bounces), max_bounces);
  }
  // Every ray cast (empty in rows from before its column): a whole number, at least the
  // camera rays, which it counts.
  if (const std::string& cast = row.text("rays_cast"); !cast.empty()) {
    const double n = row.number("rays_cast"), camera = row.text("rays").empty() ? 0 : row.number("rays");
    if (!(n >= camera && n == std::floor(n)))
      return fmt::format("rays_cast '{}' is not a whole number of at least the row's rays", printable(cast));
  }
  // Density: a foveated row's fixed or adaptive; an adaptive one names its threshold and
  // levels (increasing scales joined by ';') and has no single scale.
  const std::string& density = row.text("density");
  if (!density.empty() && density != "fixed" && density != "adaptive")
    return fmt::format("density '{}' is not fixed or adaptive", printable(density));
  if (!density.empty() && kind != row_kind::foveated)
    return fmt::format("density '{}' on a {} row (only foveated rows have one)", density, row_kind_name(kind));
  const bool adaptive = density == "adaptive";
  if (adaptive != !row.text("adaptive_threshold").empty() || adaptive != !row.text("levels").empty() ||
      (adaptive && !row.text("scale").empty()))
    return "an adaptive row names its threshold and levels and no scale; no other row does";
  if (adaptive) {
    std::vector<double> scales;
    std::stringstream in(row.text("levels"));
    std::string v;
    while (std::getline(in, v, ';')) {
      char* end = nullptr;
      scales.push_back(std::strtod(v.c_str(), &end));
      if (v.empty() || *end) return fmt::format("levels '{}' is not scales joined by ';'", printable(row.text("levels")));
    }
    if (!levels_problem(scales).empty())
      return fmt::format("levels '{}' is not 2..{} increasing positive scales", printable(row.text("levels")), max_levels);
  }
  // Reuse: a fixed set's single frame without a ray floor, named with its settings and
  // carrying what reuse measured; no other row carries any of it.
  const std::string& reuse = row.text("reuse");
  if (!reuse.empty() && reuse != "temporal") return fmt::format("reuse '{}' is not temporal", printable(reuse));
  if (!reuse.empty() && (density != "fixed" || !row.text("taa_frames").empty() || !row.text("ray_floor").empty()))
    return "a reuse row is a fixed set's single frame without a ray floor";
  for (const char* c : {"reuse_settings", "reuse_kept", "reuse_rays_ratio", "reuse_rays_cast_ratio", "reuse_trace_ratio",
                        "reuse_trace_ratio_lo", "reuse_trace_ratio_hi"})
    if (row.text(c).empty() != reuse.empty()) return fmt::format("{} is given on a reuse row and on no other", c);
  for (const char* c : {"reuse_video_jod_traced", "reuse_flicker_traced"})
    if (reuse.empty() && !row.text(c).empty()) return fmt::format("{} on a row without reuse", c);
  if (!reuse.empty() && !(row.number("reuse_trace_ratio_lo") <= row.number("reuse_trace_ratio") &&
                          row.number("reuse_trace_ratio") <= row.number("reuse_trace_ratio_hi")))
    return "reuse_trace_ratio does not lie within its _lo and _hi";
  for (const char* list : {"error_profile", "speedup_samples", "ladder_samples", "level_rays"}) {
    std::stringstream profile(row.text(list));
    std::string v;
    const bool positive = std::string(list) != "error_profile" && std::string(list) != "level_rays";
    while (std::getline(profile, v, ';')) {
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (v.empty() || *end || !(positive ? x > 0 : x >= 0) || !std::isfinite(x))
        return fmt::format("{} '{}' is not numbers {} joined by ';'", list, printable(row.text(list)), positive ? "> 0" : ">= 0");
    }
  }
  // Each numeric column's range, by its name.
  struct range { double lo, hi; bool lo_open, inf_ok; };
  auto rule = [](const std::string& c) -> std::optional<range> {
    auto starts = [&](const char* p) { return c.rfind(p, 0) == 0; };
    if (c == "speedup_samples" || c == "ladder_samples" || c == "level_rays" || c == "taa_frames")
      return std::nullopt;  // checked above
    constexpr double inf = std::numeric_limits<double>::infinity(), big = std::numeric_limits<double>::max();
    if (starts("psnr") || starts("noise_floor_psnr") || c == "foveated_psnr") return range{0, inf, false, true};
    if (starts("ssim")) return range{-1, 1, false, false};
    if (starts("flip") || starts("foveated_flip") || starts("noise_floor_flip") || starts("geometry_") || c == "pixel_fraction")
      return range{0, 1, c == "pixel_fraction", false};
    if (c == "frame_ms" || starts("frame_ms_") || starts("full_ms") || starts("speedup") || c == "spp" || c == "frames" ||
        c == "reference_spp")
      return range{0, big, true, false};
    if (c == "scale") return range{0, 10, true, false};
    if (c == "adaptive_threshold") return range{0, max_adaptive_threshold, false, false};
    if (c == "reuse_kept") return range{0, 1, false, false};
    if (starts("reuse_rays") || starts("reuse_trace_ratio")) return range{0, big, true, false};
    if (c == "reuse_video_jod_traced") return range{-big, 10, false, false};
    if (c == "reuse_flicker_traced") return range{0, big, false, false};
    if (starts("jod") || starts("noise_floor_jod") || starts("video_jod") || starts("noise_floor_video_jod"))
      return range{-big, 10, false, false};
    if (c == "k") return range{1, 32, false, false};
    if (c == "gaze_x" || c == "gaze_y" || c == "points_traced" || c == "rays" || c == "full_rays" || c == "trace_ms" ||
        c == "reconstruct_ms" || c == "foveated_error" || c == "noise_floor_foveated_error" || starts("flicker") ||
        c == "trace_cpu_ms" || c == "reconstruct_cpu_ms" || c == "full_cpu_ms")
      return range{0, big, false, false};
    return std::nullopt;
  };
  for (const auto& [column, text] : row.cells) {
    const auto r = rule(column);
    if (text.empty() || !r) continue;
    const double v = row.number(column);
    const bool ok = std::isinf(v) ? (r->inf_ok && v > 0) : (r->lo_open ? v > r->lo : v >= r->lo) && v <= r->hi;
    const std::string upper = r->inf_ok ? "inf]" : r->hi == std::numeric_limits<double>::max() ? "inf)" : fmt::format("{:g}]", r->hi);
    if (!ok) return fmt::format("{} {} lies outside {}{:g}, {}", column, printable(text), r->lo_open ? "(" : "[", r->lo, upper);
  }
  return "";
}

std::string integrator_text(const result_row& row) {
  if (row.text("integrator") != "path") return "direct";
  const std::string& n = row.text("bounces");
  return fmt::format("path, {} bounce{}", n, n == "1" ? "" : "s");
}

std::vector<result_row> read_results(const std::string& path, bool older_ok) {
  std::istringstream in(read_input_file(path, max_results_bytes, "results.csv"));
  auto chomp = [](std::string& s) {  // a file saved with CRLF line ends reads the same
    if (!s.empty() && s.back() == '\r') s.pop_back();
  };
  std::string line;
  if (!std::getline(in, line) || in.eof()) throw std::runtime_error(fmt::format("{}: no header", path));
  chomp(line);
  const std::vector<std::string> header = split_csv(line);
  // An older fovbench's header: without rays_cast, before that without the integrator, before
  // that without the acuity columns, before that without the density columns, and before that
  // without the steady-state ones too.
  auto without = [](std::set<std::string> later) {
    std::vector<std::string> columns = result_columns();
    columns.erase(std::remove_if(columns.begin(), columns.end(), [&](const std::string& c) { return later.count(c) > 0; }),
                  columns.end());
    return columns;
  };
  const std::set<std::string>& reuse_columns = reuse_result_columns();
  auto before_reuse = [&](std::set<std::string> later) {
    later.insert(reuse_columns.begin(), reuse_columns.end());
    return without(later);
  };
  const bool older =
      older_ok && (header == before_reuse({}) || header == before_reuse({"rays_cast"}) ||
                   header == before_reuse({"rays_cast", "integrator", "bounces"}) ||
                   header == before_reuse({"rays_cast", "integrator", "bounces", "acuity", "sampler"}) ||
                   header == before_reuse({"rays_cast", "integrator", "bounces", "acuity", "sampler", "density",
                                           "adaptive_threshold", "levels", "level_rays"}) ||
                   header == before_reuse({"rays_cast", "integrator", "bounces", "acuity", "sampler", "density",
                                           "adaptive_threshold", "levels", "level_rays", "taa_frames", "taa_pattern"}));
  if (header != result_columns() && !older)
    throw std::runtime_error(fmt::format("{}:1: not a results.csv of this fovbench (columns differ); use another -o", path));
  static const std::set<std::string> text_columns = {"scene",  "gaze",         "kind",   "method",         "texture_footprint", "taa_pattern",
                                                     "fovea",  "acuity", "sampler", "display", "timing_flag", "density", "levels", "level_rays", "integrator",  "device", "neighbours", "render_settings", "error_profile", "reuse", "reuse_settings",
                                                     "speedup_samples", "ladder_samples"};
  std::vector<result_row> rows;
  std::map<std::string, int> first_line;  // by key
  for (int number = 2; std::getline(in, line); ++number) {
    if (in.eof()) break;  // a torn last line
    chomp(line);
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv(line);
    if (cells.size() != header.size())
      throw std::runtime_error(fmt::format("{}:{}: {} cells, expected {}", path, number, cells.size(), header.size()));
    result_row r;
    if (older) r.cells["taa_frames"] = r.cells["taa_pattern"] = "";  // single frames
    if (older) r.cells["adaptive_threshold"] = r.cells["levels"] = r.cells["level_rays"] = "";  // fixed sets
    if (older) r.cells["rays_cast"] = "";  // not counted then
    if (older)
      for (const std::string& c : reuse_columns) r.cells[c] = "";  // no reuse rows then
    for (size_t i = 0; i < cells.size(); ++i) {
      const std::string& c = cells[i];
      // A number as fovbench writes it: finite, or inf (a PSNR of identical images); empty
      // where it does not apply. nan is never written (an empty cell is).
      if (!c.empty() && !text_columns.count(header[i])) {
        char* end = nullptr;
        const double v = std::strtod(c.c_str(), &end);
        if (*end || std::isnan(v) || (std::isinf(v) && c != "inf" && c != "-inf"))
          throw std::runtime_error(
              fmt::format("{}:{}: {} '{}' is not a number fovbench writes", path, number, header[i], printable(c)));
      }
      r.cells[header[i]] = c;
    }
    if (older && !r.cells.count("density")) r.cells["density"] = r.text("kind") == "foveated" ? "fixed" : "";
    if (older && !r.cells.count("acuity")) r.cells["acuity"] = "csf";  // before acuity models: the thesis's
    if (older && !r.cells.count("sampler")) r.cells["sampler"] = "poisson";  // ... and its darts
    if (older && !r.cells.count("integrator")) r.cells["integrator"] = "direct", r.cells["bounces"] = "";  // before path tracing
    if (const std::string why = result_row_problem(r); !why.empty())
      throw std::runtime_error(fmt::format("{}:{}: {} (not a row fovbench writes)", path, number, why));
    if (const auto [it, added] = first_line.emplace(r.key(), number); !added)
      throw std::runtime_error(fmt::format("{}:{}: the same configuration as line {} (a results.csv holds each once)", path,
                                           number, it->second));
    rows.push_back(std::move(r));
  }
  return rows;
}

results_writer::results_writer(const std::string& path) : log_(path, line_log::mode::create_or_open) {
  if (!log_.empty()) return;  // resuming (a torn last row was cut)
  std::string header;
  for (const std::string& c : result_columns()) header += (header.empty() ? "" : ",") + c;
  log_.append_line(header);
}

void results_writer::append(const result_row& row) {
  if (const std::string why = result_row_problem(row); !why.empty())  // a defect in fovbench, never data
    throw std::logic_error(fmt::format("fovbench made a row it would not read back: {}", why));
  std::string line;
  for (const std::string& c : result_columns()) line += (line.empty() ? "" : ",") + csv_cell(row.text(c));
  log_.append_line(line);
}

}  // namespace fov
