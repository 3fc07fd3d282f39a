#include "report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <fmt/format.h>

#include "fov/pointset_io.h"
#include "fov/speedup.h"
#include "plot.h"

namespace fov {

namespace {

// A number of a row's cell, read back by read_results (so finite); strtod, unlike std::stod,
// does not throw on a subnormal.
double to_number(const std::string& text) { return std::strtod(text.c_str(), nullptr); }

// The report's unit: the rows of one scene under one integrator (integrator_text), as single
// frames or in one steady state under TAA (taa_frames and taa_pattern): each is judged on its
// own, against its own baselines.
struct sweep_part {
  std::string scene, taa_frames, taa_pattern, integrator = "direct";
  bool operator==(const sweep_part& o) const {
    return scene == o.scene && taa_frames == o.taa_frames && taa_pattern == o.taa_pattern && integrator == o.integrator;
  }
  // Reuse rows are measured along the temporal path, not as single frames: they have a
  // section of their own (reuse_markdown) and no part.
  bool holds(const result_row& r) const {
    return r.text("reuse").empty() && r.text("scene") == scene && r.text("taa_frames") == taa_frames && r.text("taa_pattern") == taa_pattern &&
           integrator_text(r) == integrator;
  }
};

std::vector<sweep_part> scenes_of(const std::vector<result_row>& rows) {
  std::vector<sweep_part> out;
  for (const result_row& r : rows) {
    if (!r.text("reuse").empty()) continue;
    const sweep_part part{r.text("scene"), r.text("taa_frames"), r.text("taa_pattern"), integrator_text(r)};
    if (std::find(out.begin(), out.end(), part) == out.end()) out.push_back(part);
  }
  return out;
}

}  // namespace

std::string short_scene(const std::string& s) {
  const std::string name = std::filesystem::path(s.substr(s.rfind(':') == std::string::npos ? 0 : s.rfind(':') + 1)).filename().string();
  return s.rfind("env:", 0) == 0 ? "env:" + name : name;
}

namespace {

// A configuration of knobs (kind, scale or pixel fraction, method, k, spp) averaged over
// the gazes of the sweep: the gaze is not a knob, so the trade is judged on the average.
struct knob_mean {
  row_kind kind{};
  std::string method, k, scale, fraction, spp, floor;
  std::string threshold;  // an adaptive configuration's (density adaptive); "" for a fixed set
  double frame_ms = 0, frame_lo = 0, frame_hi = 0, full_ms = 0, speedup = 0, speedup_lo = 0, speedup_hi = 0;
  double psnr = 0, psnr_fovea = 0, foveated_error = 0;
  double flip = 0, flip_fovea = 0, flip_p99 = 0, foveated_flip = 0, foveated_flip_p99 = 0, foveated_flip_worst_band = 0;
  double jod = 0, jod_nonfoveated = 0;
  double rays = 0, points = 0;  // rays cast and points traced per frame
  std::vector<double> paired;  // per-repetition full / frame ratios of every gaze
  std::vector<double> ladder;  // full rows: per repetition, this spp's time over the lowest's
  int gazes = 0;
  std::string label() const {
    if (kind == row_kind::full) return fmt::format("full {}spp", spp);
    if (kind == row_kind::falloff) return fmt::format("fall s{} {}-{}spp", scale, spp, floor);
    const std::string k_text = method == "nn" ? "" : " k" + k;
    if (kind == row_kind::uniform) return fmt::format("u{} {} {}spp{}", fraction.substr(0, 4), method, spp, k_text);
    if (!threshold.empty()) return fmt::format("adaptive T{} {} {}spp{}", threshold, method, spp, k_text);
    if (!floor.empty()) return fmt::format("s{} {} {}-{}spp{}", scale, method, spp, floor, k_text);
    return fmt::format("s{} {} {}spp{}", scale, method, spp, k_text);
  }
  // The mean of a named error column.
  double error(const std::string& metric) const {
    if (metric == "jod_loss") return 10 - jod;  // JOD below no difference: an error to minimise
    if (metric == "foveated_flip") return foveated_flip;
    if (metric == "foveated_flip_worst_band") return foveated_flip_worst_band;
    if (metric == "foveated_flip_p99") return foveated_flip_p99;
    if (metric == "flip") return flip;
    if (metric == "flip_fovea") return flip_fovea;
    if (metric == "flip_p99") return flip_p99;
    return foveated_error;
  }
};

std::vector<knob_mean> knob_means(const std::vector<const result_row*>& rows) {
  std::vector<knob_mean> out;
  auto mse = [](double psnr) { return std::isinf(psnr) ? 0.0 : 255.0 * 255.0 / std::pow(10.0, psnr / 10); };
  for (const result_row* r : rows) {
    knob_mean id;
    id.kind = r->kind(), id.method = r->text("method"), id.k = r->text("k"), id.scale = r->text("scale");
    id.fraction = r->text("pixel_fraction"), id.spp = r->text("spp"), id.floor = r->text("ray_floor");
    id.threshold = r->text("adaptive_threshold");
    auto it = std::find_if(out.begin(), out.end(), [&](const knob_mean& m) {
      return m.kind == id.kind && m.method == id.method && m.k == id.k && m.scale == id.scale && m.fraction == id.fraction &&
             m.spp == id.spp && m.floor == id.floor && m.threshold == id.threshold;
    });
    if (it == out.end()) it = out.insert(out.end(), id);
    it->frame_ms += r->number("frame_ms"), it->frame_lo += r->number("frame_ms_lo"), it->frame_hi += r->number("frame_ms_hi");
    it->full_ms += r->number("full_ms"), it->speedup += r->number("speedup");
    it->speedup_lo += r->number("speedup_lo"), it->speedup_hi += r->number("speedup_hi");
    // PSNRs are averaged as mean squared errors (an identical band, PSNR inf, adds 0).
    it->psnr += mse(r->number("psnr")), it->psnr_fovea += mse(r->number("psnr_fovea"));
    it->foveated_error += r->number("foveated_error");
    it->flip += r->number("flip"), it->flip_fovea += r->number("flip_fovea"), it->flip_p99 += r->number("flip_p99");
    it->foveated_flip += r->number("foveated_flip"), it->foveated_flip_p99 += r->number("foveated_flip_p99");
    it->foveated_flip_worst_band += r->number("foveated_flip_worst_band");
    it->jod += r->number("jod"), it->jod_nonfoveated += r->number("jod_nonfoveated");
    it->rays += r->number("rays"), it->points += r->text("points_traced").empty() ? 0 : r->number("points_traced");
    for (const char* column : {"speedup_samples", "ladder_samples"}) {
      std::vector<double>& to = std::string(column) == "speedup_samples" ? it->paired : it->ladder;
      if (column[0] == 'l' && !to.empty()) continue;  // the ladder is the scene's: one gaze's copy
      std::stringstream in(r->text(column));
      std::string v;
      while (std::getline(in, v, ';')) to.push_back(to_number(v));
    }
    ++it->gazes;
  }
  for (knob_mean& m : out) {
    const double n = m.gazes;
    for (double* v : {&m.frame_ms, &m.frame_lo, &m.frame_hi, &m.full_ms, &m.speedup, &m.speedup_lo, &m.speedup_hi,
                      &m.foveated_error, &m.flip, &m.flip_fovea, &m.flip_p99, &m.foveated_flip, &m.foveated_flip_p99,
                      &m.foveated_flip_worst_band, &m.jod, &m.jod_nonfoveated, &m.rays, &m.points})
      *v /= n;
    auto psnr = [](double mse) { return mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : INFINITY; };
    m.psnr = psnr(m.psnr / n), m.psnr_fovea = psnr(m.psnr_fovea / n);
  }
  return out;
}

// The error the figures and the headline use: the foveated FLIP, or the foveated RMSE
// when the sweep ran with --no-flip.
std::string headline_metric(const std::vector<knob_mean>& means) {
  for (const knob_mean& m : means)
    if (!std::isnan(m.foveated_flip)) return "foveated_flip";
  return "foveated_error";
}

// Indices of the front of the means whose kind is in `kinds`.
std::vector<size_t> front_of(const std::vector<knob_mean>& means, const std::set<row_kind>& kinds, const std::string& metric) {
  std::vector<double> x, y;
  for (const knob_mean& m : means) {
    const bool in = kinds.count(m.kind) > 0;
    x.push_back(in ? m.frame_ms : NAN), y.push_back(in ? m.error(metric) : NAN);
  }
  return pareto_front(x, y);
}

std::vector<std::pair<double, double>> points_of(const std::vector<knob_mean>& means, const std::vector<size_t>& front,
                                                 const std::string& metric) {
  std::vector<std::pair<double, double>> out;
  for (size_t i : front) out.emplace_back(means[i].frame_ms, means[i].error(metric));
  return out;
}

// Foveated schemes (sparse sets, and the full grid at a foveated sampling rate) against the
// baselines a user would render without foveation.
const std::set<row_kind> foveated_kind{row_kind::foveated, row_kind::falloff},
    baseline_kinds{row_kind::full, row_kind::uniform};

std::vector<const result_row*> rows_of(const std::vector<result_row>& rows, const sweep_part& part) {
  std::vector<const result_row*> mine;
  for (const result_row& r : rows)
    if (part.holds(r)) mine.push_back(&r);
  return mine;
}

// "builtin", or "builtin, TAA steady state (16 frames, mirror)".
std::string part_title(const sweep_part& part) {
  const std::string scene = short_scene(part.scene) + (part.integrator == "direct" ? "" : " (" + part.integrator + ")");
  if (part.taa_frames.empty()) return scene;
  return fmt::format("{}, TAA steady state ({} frames, {})", scene, part.taa_frames, part.taa_pattern);
}

// The Pareto figure of one scene: every configuration's mean (frame time with its
// repetitions' min-max as a horizontal bar, error or JOD), both fronts drawn and their
// points labelled. JOD is better higher; the errors lower.
plot_panel pareto_panel(const sweep_part& scene, const std::vector<knob_mean>& means, const std::string& metric) {
  const bool jod = metric == "jod";
  plot_panel p;
  p.title = fmt::format("Pareto fronts: {} (mean over gazes)", part_title(scene));
  p.x_label = "frame time (ms, log scale; bars: min-max of the repetitions)";
  p.y_label = jod ? "JOD (FovVideoVDP, foveated; 10 = no visible difference)" : metric + " vs converged reference";
  p.log_x = true;
  // Fronts minimise (time, error): JOD enters as its distance below 10.
  const std::string key = jod ? "jod_loss" : metric;
  const std::vector<size_t> fov_front = front_of(means, foveated_kind, key), base_front = front_of(means, baseline_kinds, key);
  auto on = [](const std::vector<size_t>& f, size_t i) { return std::find(f.begin(), f.end(), i) != f.end(); };
  auto value = [&](size_t i) { return jod ? means[i].jod : means[i].error(metric); };
  struct group {
    std::string name;
    row_kind kind;
    std::string method, scheme;
    bool adaptive = false;
  };
  const group groups[] = {{"foveated nn", row_kind::foveated, "nn", "nn"},
                          {"foveated shepard", row_kind::foveated, "shepard", "shepard"},
                          {"foveated rbf", row_kind::foveated, "rbf", "rbf"},
                          {"adaptive (nested set refined per frame)", row_kind::foveated, "", "adaptive", true},
                          {"falloff (full grid, rays by eccentricity)", row_kind::falloff, "", "falloff"},
                          {"uniform", row_kind::uniform, "", "uniform"},
                          {"full resolution", row_kind::full, "", "full"}};
  for (const group& g : groups) {
    plot_series s;
    s.name = g.name, s.scheme = g.scheme, s.lines = false;
    for (size_t i = 0; i < means.size(); ++i) {
      if (means[i].kind != g.kind || (!g.method.empty() && means[i].method != g.method) ||
          means[i].threshold.empty() == g.adaptive)
        continue;
      s.x.push_back(means[i].frame_ms), s.y.push_back(value(i));
      s.x_lo.push_back(means[i].frame_lo), s.x_hi.push_back(means[i].frame_hi);
      const bool front = on(fov_front, i) || on(base_front, i);
      s.ringed.push_back(front);
      s.labels.push_back(front ? means[i].label() : "");
    }
    if (!s.x.empty()) p.series.push_back(s);
  }
  for (const auto& [name, front, scheme] : {std::tuple<std::string, std::vector<size_t>, std::string>{"foveated front", fov_front,
                                                                                                     "front-foveated"},
                                            {"baseline front", base_front, "front-baseline"}}) {
    plot_series f;
    f.name = name, f.scheme = scheme, f.markers = false;
    for (size_t i : front) f.x.push_back(means[i].frame_ms), f.y.push_back(value(i));
    if (!f.x.empty()) p.series.push_back(f);
  }
  return p;
}

}  // namespace

std::vector<std::string> write_bench_figures(const std::vector<result_row>& rows, const bench_options& o, const std::string& dir) {
  std::vector<plot_panel> pareto_jod, pareto, pareto_flip, profiles, speedups;
  for (const sweep_part& scene : scenes_of(rows)) {
    const std::vector<const result_row*> mine = rows_of(rows, scene);
    const std::vector<knob_mean> means = knob_means(mine);
    const std::string metric = headline_metric(means);
    if (std::any_of(means.begin(), means.end(), [](const knob_mean& m) { return !std::isnan(m.jod); }))
      pareto_jod.push_back(pareto_panel(scene, means, "jod"));
    pareto.push_back(pareto_panel(scene, means, metric));
    if (metric == "foveated_flip") pareto_flip.push_back(pareto_panel(scene, means, "flip"));

    // Error by eccentricity: each method at the smallest and largest scale, and the
    // full-resolution frame, at the first gaze, the most rays per sample (every point
    // casting them: no --point-ray-floors rows) and the first k listed (nn: 1).
    plot_panel e;
    const std::string gaze = mine.empty() ? "" : mine[0]->text("gaze");
    double lo_scale = 1e9, hi_scale = 0, top_spp = 0;
    for (const result_row* r : mine) {
      if (r->kind() == row_kind::foveated && r->text("density") != "adaptive")
        lo_scale = std::min(lo_scale, r->number("scale")), hi_scale = std::max(hi_scale, r->number("scale"));
      top_spp = std::max(top_spp, r->number("spp"));
    }
    e.title = fmt::format("Error by eccentricity: {} (gaze {}, {:g} spp)", part_title(scene), gaze, top_spp);
    e.x_label = "eccentricity (degrees)";
    e.y_label = "RMSE vs converged reference (full scale)";
    std::set<std::string> drawn;
    for (const result_row* r : mine) {
      const double s = r->number("scale");
      const bool full = r->kind() == row_kind::full;
      if (r->text("gaze") != gaze || r->number("spp") != top_spp) continue;
      if (!full && (r->kind() != row_kind::foveated || (s != lo_scale && s != hi_scale) || !r->text("ray_floor").empty() ||
                    r->text("density") == "adaptive"))
        continue;
      const std::string id = r->text("kind") + "|" + r->text("method") + "|" + r->text("scale");
      if (drawn.count(id) || (!full && r->text("method") != "nn" && r->text("k") != std::to_string(o.ks.empty() ? 5 : o.ks[0])))
        continue;
      drawn.insert(id);
      plot_series line;
      line.name = full ? "full resolution" : fmt::format("{} k={} s={}", r->text("method"), r->text("k"), r->text("scale"));
      line.scheme = full ? "full" : r->text("method");
      line.style = !full && s == hi_scale && s != lo_scale ? "dashed" : "solid";  // the larger scale dashed
      line.markers = false;
      std::stringstream in(r->text("error_profile"));
      std::string v;
      for (int bin = 0; std::getline(in, v, ';'); ++bin) line.x.push_back((bin + 0.5) * 2.5), line.y.push_back(to_number(v));
      e.series.push_back(line);
    }
    profiles.push_back(e);

    // Same-spp speedup against scale: per method (at the first k listed; nn at 1) and spp,
    // every point casting spp rays (no --point-ray-floors rows), means over gazes, bars from
    // the slowest to the fastest paired repetition.
    plot_panel sp;
    sp.title = "Speedup over full resolution, same spp: " + part_title(scene) + " (mean over gazes)";
    sp.x_label = "point-set scale s";
    sp.y_label = "speedup (full-resolution ms / frame ms)";
    const std::string first_k = std::to_string(o.ks.empty() ? 5 : o.ks[0]);
    // One colour per method; the spp sets the line style.
    std::map<std::pair<std::string, double>, std::map<double, const knob_mean*>> curves;
    for (const knob_mean& m : means) {
      if (m.kind != row_kind::foveated || (m.method != "nn" && m.k != first_k) || !m.floor.empty() || !m.threshold.empty())
        continue;
      curves[{m.method, to_number(m.spp)}][to_number(m.scale)] = &m;
    }
    std::vector<double> spps;
    for (const auto& [id, points] : curves)
      if (std::find(spps.begin(), spps.end(), id.second) == spps.end()) spps.push_back(id.second);
    std::sort(spps.begin(), spps.end());
    const char* styles[] = {"solid", "dashed", "dotted", "dashdot"};
    for (const auto& [id, points] : curves) {
      plot_series s;
      const knob_mean& any = *points.begin()->second;
      s.name = fmt::format("{} k={} spp={}", id.first, any.k, any.spp);
      s.scheme = id.first;
      s.style = styles[size_t(std::find(spps.begin(), spps.end(), id.second) - spps.begin()) % 4];
      for (const auto& [scale, m] : points)
        s.x.push_back(scale), s.y.push_back(m->speedup), s.y_lo.push_back(m->speedup_lo), s.y_hi.push_back(m->speedup_hi);
      sp.series.push_back(s);
    }
    speedups.push_back(sp);
  }
  std::vector<std::string> problems;
  auto draw = [&](const std::vector<plot_panel>& panels, const char* name) {
    if (panels.empty()) return;
    if (const std::string why = write_plot(panels, dir + "/" + name); !why.empty()) problems.push_back(why);
  };
  draw(pareto_jod, "pareto_jod");
  draw(pareto, "pareto");
  draw(pareto_flip, "pareto_flip");
  draw(profiles, "error_by_eccentricity");
  draw(speedups, "speedup_vs_scale");
  return problems;
}

namespace {

std::string fmt_db(double v) { return std::isfinite(v) ? fmt::format("{:.2f}", v) : std::string("inf"); }
std::string fmt_err(double v) { return std::isnan(v) ? std::string("-") : fmt::format("{:.4f}", v); }
std::string fmt_jod(double v) { return std::isnan(v) ? std::string("-") : fmt::format("{:.2f}", v); }

// min / median / max of a column over rows, as text.
std::string spread_of(const std::vector<const result_row*>& rows, const std::string& column, const char* format) {
  std::vector<double> v;
  for (const result_row* r : rows)
    if (!std::isnan(r->number(column))) v.push_back(r->number(column));
  if (v.empty()) return "-";
  std::sort(v.begin(), v.end());
  return fmt::format(fmt::runtime(format), v.front()) + " / " + fmt::format(fmt::runtime(format), v[v.size() / 2]) + " / " +
         fmt::format(fmt::runtime(format), v.back());
}

std::string equal_error_table(const std::vector<knob_mean>& means, const std::string& metric) {
  const std::vector<size_t> ff = front_of(means, foveated_kind, metric), bf = front_of(means, baseline_kinds, metric);
  const auto fov = points_of(means, ff, metric), base = points_of(means, bf, metric);
  if (fov.empty() || base.empty()) return "No foveated or no baseline configuration to compare.\n";
  auto range = [](const std::vector<std::pair<double, double>>& f) {
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& p : f) lo = std::min(lo, p.second), hi = std::max(hi, p.second);
    return std::make_pair(lo, hi);
  };
  const auto [flo, fhi] = range(fov);
  const auto [blo, bhi] = range(base);
  const double lo = std::max(flo, blo), hi = std::min(fhi, bhi);
  std::string md;
  if (!(lo < hi)) {
    md += fmt::format("The fronts share no error level: foveated {:.4f}..{:.4f}, baselines {:.4f}..{:.4f}. ", flo, fhi, blo, bhi);
    md += flo > bhi ? "Every baseline configuration errs less than the best foveated one.\n"
                    : blo > fhi ? "Every foveated configuration on the front errs less than the best baseline.\n"
                                : "\n";
    return md;
  }
  md += fmt::format("| {} | foveated ms | best baseline ms | equal-error speedup |\n|---:|---:|---:|---:|\n", metric);
  for (int i = 0; i < 5; ++i) {
    // Log-spaced, worst first; the ends exactly the overlap's.
    const double e = i == 0 ? hi : i == 4 ? lo : std::exp(std::log(hi) + (std::log(lo) - std::log(hi)) * i / 4.0);
    const double tf = time_at_error(fov, e), tb = time_at_error(base, e);
    md += fmt::format("| {:.4f} | {:.1f} | {:.1f} | {:.2f}x |\n", e, tf, tb, tb / tf);
  }
  md += fmt::format("\n(Error levels span the overlap of the two fronts, {:.4f}..{:.4f}; times interpolated along each front "
                    "in log time; below 1x foveation is slower for the same error.)\n", lo, hi);
  return md;
}

// The verdict in JOD: at the quality of each full-resolution frame (its mean JOD over the
// gazes), the fastest foveated configuration that reaches it, priced by chaining its paired
// ratios with the ladder's (fov::chained_speedup), with a 95 % bootstrap interval.
struct jod_verdict {
  std::vector<std::string> lines;
  int pays = 0, loses = 0, inconclusive = 0, unreached = 0;
};

// The full-resolution means with JOD, by spp.
std::vector<const knob_mean*> full_means(const std::vector<knob_mean>& means) {
  std::vector<const knob_mean*> fulls;
  for (const knob_mean& m : means)
    if (m.kind == row_kind::full && !std::isnan(m.jod)) fulls.push_back(&m);
  std::sort(fulls.begin(), fulls.end(), [](const knob_mean* a, const knob_mean* b) { return to_number(a->spp) < to_number(b->spp); });
  return fulls;
}

// The reference's noise floor in JOD, averaged over the part's gazes (NaN without rows).
double noise_floor_jod(const std::vector<const result_row*>& rows) {
  double floor = 0;
  int gazes = 0;
  std::set<std::string> seen;
  for (const result_row* r : rows)
    if (seen.insert(r->text("gaze")).second) floor += r->number("noise_floor_jod"), ++gazes;
  return gazes ? floor / gazes : NAN;
}

// Among `candidates`, the fastest (by its chained speedup's estimate) whose JOD reaches the
// full-resolution frame b's, with that speedup; else nullptr and, in `closest`, the best JOD
// short of it.
struct reaching {
  const knob_mean* best = nullptr;
  speedup_interval interval;
  const knob_mean* closest = nullptr;
};
reaching fastest_reaching(const knob_mean& b, const std::vector<const knob_mean*>& candidates,
                          const std::vector<const knob_mean*>& fulls) {
  auto ladder_of = [&](const std::string& spp) -> const std::vector<double>* {
    for (const knob_mean* f : fulls)
      if (f->spp == spp) return &f->ladder;
    return nullptr;
  };
  reaching out;
  const std::vector<double>* lb = ladder_of(b.spp);
  for (const knob_mean* c : candidates) {
    if (std::isnan(c->jod)) continue;
    if (c->jod < b.jod) {
      if (!out.closest || c->jod > out.closest->jod) out.closest = c;
      continue;
    }
    const std::vector<double>* lc = ladder_of(c->spp);
    if (!lb || !lc || lb->size() != lc->size() || lb->empty() || c->paired.empty()) continue;
    std::vector<double> rung;
    for (size_t i = 0; i < lb->size(); ++i) rung.push_back((*lb)[i] / (*lc)[i]);
    const speedup_interval iv = chained_speedup(c->paired, rung);
    if (!out.best || iv.estimate > out.interval.estimate) out.best = c, out.interval = iv;
  }
  return out;
}

jod_verdict verdict_in_jod(const std::vector<knob_mean>& means) {
  jod_verdict v;
  const std::vector<const knob_mean*> fulls = full_means(means);
  std::vector<const knob_mean*> foveated;
  for (const knob_mean& m : means)
    if (foveated_kind.count(m.kind)) foveated.push_back(&m);
  for (const knob_mean* b : fulls) {
    const reaching r = fastest_reaching(*b, foveated, fulls);
    const knob_mean* best = r.best;
    const speedup_interval& best_iv = r.interval;
    if (!best) {
      ++v.unreached;
      v.lines.push_back(fmt::format("No foveated configuration reaches {:.2f} JOD (full resolution, {} spp){}.", b->jod, b->spp,
                                    r.closest ? fmt::format("; the best reaches {:.2f} ({})", r.closest->jod, r.closest->label()) : ""));
      continue;
    }
    std::string judgement;
    if (best_iv.contains_one()) judgement = "inconclusive on this machine: the interval contains 1", ++v.inconclusive;
    else if (best_iv.lo > 1) judgement = "faster", ++v.pays;
    else judgement = "slower", ++v.loses;
    v.lines.push_back(fmt::format("At {:.2f} JOD (full resolution, {} spp) the best foveated configuration, {} ({:.2f} JOD), is "
                                  "{:.2f}x as fast (95 % interval {:.2f}-{:.2f}): {}.",
                                  b->jod, b->spp, best->label(), best->jod, best_iv.estimate, best_iv.lo, best_iv.hi, judgement));
  }
  return v;
}

std::string verdict_sentence(const jod_verdict& v) {
  if (v.lines.empty()) return "No verdict: the sweep has no full-resolution rows with JOD (--baselines full, without --no-jod).";
  if (v.pays) return fmt::format("Foveation pays at {} of {} full-resolution quality levels.", v.pays, v.lines.size());
  if (v.inconclusive) return fmt::format("Inconclusive on this machine at {} of {} quality levels; foveation pays at none.",
                                         v.inconclusive, v.lines.size());
  return "Foveation does not pay: at every quality level it is slower or never reaches it.";
}

// The scheme a configuration belongs to; full resolution belongs to none.
std::optional<scheme> scheme_of(row_kind kind, bool grid_fovea, bool adaptive) {
  switch (kind) {
    case row_kind::foveated: return adaptive ? scheme::adaptive : grid_fovea ? scheme::hybrid : scheme::sparse;
    case row_kind::falloff: return scheme::falloff;
    case row_kind::uniform: return scheme::lower_resolution;
    case row_kind::full: break;
  }
  return std::nullopt;
}

}  // namespace

double goal_speedup(double ppd) {
  if (ppd < 23.5) return 1.5;
  if (ppd >= 45 && ppd <= 55) return 5;
  if (ppd >= 69.5) return 10;
  return NAN;
}

std::string answer_title(const scheme_answer& a) { return part_title({a.scene, a.taa_frames, a.taa_pattern, a.integrator}); }

std::vector<scheme_answer> scheme_answers_by_level(const std::vector<result_row>& rows) {
  std::vector<scheme_answer> out;
  for (const sweep_part& part : scenes_of(rows)) {
    const std::vector<const result_row*> mine = rows_of(rows, part);
    const std::vector<knob_mean> means = knob_means(mine);
    const std::vector<const knob_mean*> fulls = full_means(means);
    const double floor = noise_floor_jod(mine);
    const result_row& first = *mine.front();
    const std::string& fovea = first.text("fovea");  // darts, grid or grid-P.PP (the spacing)
    const bool grid = fovea.rfind("grid", 0) == 0;
    for (const auto& [name, which] : scheme_labels) {
      std::vector<const knob_mean*> candidates;
      for (const knob_mean& m : means)
        if (scheme_of(m.kind, grid, !m.threshold.empty()) == which && !std::isnan(m.jod)) candidates.push_back(&m);
      for (const knob_mean* yard : fulls) {
        const reaching r = fastest_reaching(*yard, candidates, fulls);
        const knob_mean* shown = r.best ? r.best : r.closest;
        if (!shown) continue;  // no configuration, or one reaching it unpriced (no ladder): no answer
        scheme_answer a;
        a.scene = part.scene, a.taa_frames = part.taa_frames, a.taa_pattern = part.taa_pattern, a.integrator = part.integrator;
        a.display = first.text("display"), a.ppd = first.number("ppd"), a.pixels = first.number("full_rays") / first.number("spp");
        a.noise_floor_jod = floor;
        a.target_jod = NAN;
        a.yardstick_spp = to_number(yard->spp), a.yardstick_jod = yard->jod, a.yardstick_ms = yard->frame_ms;
        a.yardstick_rays = yard->rays;
        a.scheme = which;
        a.reached = r.best != nullptr;
        a.best = shown->label() + (a.scheme == scheme::hybrid ? " " + fovea : ""), a.best_jod = shown->jod, a.best_ms = shown->frame_ms, a.best_rays = shown->rays;
        a.best_points = shown->points;
        a.speedup = r.best ? r.interval : speedup_interval{NAN, NAN, NAN};
        out.push_back(a);
      }
    }
  }
  return out;
}

std::vector<scheme_answer> at_goal(const std::vector<scheme_answer>& by_level, double target_jod) {
  // Per scene, steady state and display: the fewest spp whose full frame reaches the target,
  // else the spp of the best full frame.
  using place = std::tuple<std::string, std::string, std::string, std::string, std::string>;
  std::map<place, std::pair<double, double>> yardstick;  // spp, JOD
  auto place_of = [](const scheme_answer& a) { return place{a.scene, a.taa_frames, a.taa_pattern, a.integrator, a.display}; };
  for (const scheme_answer& a : by_level) {
    const auto [it, added] = yardstick.emplace(place_of(a), std::make_pair(a.yardstick_spp, a.yardstick_jod));
    if (added) continue;
    auto& [spp, jod] = it->second;
    const bool reaches = a.yardstick_jod >= target_jod, had_reaches = jod >= target_jod;
    if (reaches ? !had_reaches || a.yardstick_spp < spp : !had_reaches && a.yardstick_jod > jod) spp = a.yardstick_spp, jod = a.yardstick_jod;
  }
  std::vector<scheme_answer> out;
  for (const scheme_answer& a : by_level)
    if (yardstick.at(place_of(a)).first == a.yardstick_spp) out.push_back(a), out.back().target_jod = target_jod;
  return out;
}

std::string scheme_answers_markdown(const std::vector<scheme_answer>& answers) {
  std::vector<sweep_part> parts;
  for (const scheme_answer& a : answers) {
    const sweep_part p{a.scene, a.taa_frames, a.taa_pattern, a.integrator};
    if (std::find(parts.begin(), parts.end(), p) == parts.end()) parts.push_back(p);
  }
  std::string md;
  for (const sweep_part& part : parts) {
    std::vector<const scheme_answer*> mine;
    for (const scheme_answer& a : answers)
      if (sweep_part{a.scene, a.taa_frames, a.taa_pattern, a.integrator} == part) mine.push_back(&a);
    std::stable_sort(mine.begin(), mine.end(), [](const scheme_answer* a, const scheme_answer* b) { return a->ppd < b->ppd; });
    md += fmt::format("**{}**\n\n| display | ppd | pixels (M) | yardstick (JOD, ms, rays M) | reference floor (JOD) | goal |", part_title(part));
    for (const auto& [name, which] : scheme_labels) md += fmt::format(" {} |", name);
    md += "\n|---|---:|---:|---|---:|---:|---|---|---|---|\n";
    std::vector<std::string> displays;
    for (const scheme_answer* a : mine)
      if (std::find(displays.begin(), displays.end(), a->display) == displays.end()) displays.push_back(a->display);
    for (const std::string& display : displays) {
      const scheme_answer* any = nullptr;
      std::map<scheme, const scheme_answer*> cell;
      for (const scheme_answer* a : mine)
        if (a->display == display) any = any ? any : a, cell[a->scheme] = a;
      const double goal = goal_speedup(any->ppd);
      md += fmt::format("| `{}` | {:.1f} | {:.1f} | full {} spp{} ({:.2f}, {:.0f} ms, {:.2f}) | {} | {} |", display, any->ppd,
                        any->pixels / 1e6, any->yardstick_spp, any->yardstick_jod >= any->target_jod ? "" : " (below the target)",
                        any->yardstick_jod, any->yardstick_ms, any->yardstick_rays / 1e6, fmt_jod(any->noise_floor_jod),
                        std::isnan(goal) ? std::string("-") : fmt::format("{:g}x", goal));
      for (const auto& [name, which] : scheme_labels) {
        const auto it = cell.find(which);
        if (it == cell.end()) {
          md += " not measured |";
          continue;
        }
        const scheme_answer& a = *it->second;
        const std::string what = fmt::format("{}, {:.2f} JOD, {:.0f} ms, {:.2f} M rays", a.best, a.best_jod, a.best_ms, a.best_rays / 1e6);
        if (a.reached)
          md += fmt::format(" **{:.2f}x** ({:.2f}-{:.2f}, {}): {} |", a.speedup.estimate, a.speedup.lo, a.speedup.hi,
                            a.speedup.contains_one() ? "inconclusive" : a.speedup.lo > 1 ? "faster" : "slower", what);
        else md += fmt::format(" not reached ({:+.2f} JOD): {} |", a.best_jod - a.yardstick_jod, what);
      }
      md += "\n";
    }
    md += "\n";
  }
  if (!answers.empty())
    md += fmt::format("The yardstick: the cheapest full-resolution frame (fewest spp) whose JOD reaches {:.1f} (the best full frame "
                      "when none does). Each scheme's cell: the fastest of its configurations reaching the yardstick's JOD, its "
                      "speedup over the yardstick chained from paired repetitions with a 95 % bootstrap interval (faster only "
                      "when the interval lies above 1), or how far its best JOD falls short. Goal: the issue's (1.5x at FOVE's "
                      "22 ppd, 5x at about 50, 10x at 70 or more; none named between).\n",
                      answers.front().target_jod);
  return md;
}

// The reuse rows, one table line each: what reuse kept and saved along the temporal path
// against the same set traced in full, and what it cost in video JOD and flicker. "" when
// there are none.
std::string reuse_markdown(const std::vector<result_row>& rows) {
  std::string md;
  for (const result_row& r : rows) {
    if (r.text("reuse").empty()) continue;
    auto jod = [&](const char* c) { return std::isnan(r.number(c)) ? std::string("-") : fmt::format("{:.3f}", r.number(c)); };
    md += fmt::format("| {} ({}) | {} | s = {} {} k = {} | {} | {} | {:.2f} | {:.2f}x | {:.2f}x | {:.2f} ({:.2f}-{:.2f}) | "
                      "{} -> {} ({}; floor {}) | {:.4f} -> {:.4f} | {:.2f} ({:.2f}-{:.2f}) |\n",
                      short_scene(r.text("scene")), integrator_text(r), r.text("gaze"), r.text("scale"), r.text("method"),
                      r.text("k"), r.text("spp"), r.text("reuse_settings"), r.number("reuse_kept"), r.number("reuse_rays_ratio"),
                      r.number("reuse_rays_cast_ratio"), r.number("reuse_trace_ratio"), r.number("reuse_trace_ratio_lo"),
                      r.number("reuse_trace_ratio_hi"), jod("reuse_video_jod_traced"), jod("video_jod"),
                      std::isnan(r.number("video_jod")) ? std::string("-")
                                                        : fmt::format("{:+.3f}", r.number("video_jod") - r.number("reuse_video_jod_traced")),
                      jod("noise_floor_video_jod"),
                      r.number("reuse_flicker_traced"), r.number("flicker"), r.number("speedup"), r.number("speedup_lo"),
                      r.number("speedup_hi"));
  }
  if (md.empty()) return md;
  return "## Temporal reuse along the temporal path\n\n"
         "Each reuse row's set traced along the temporal path twice, every point every frame (traced) and keeping earlier "
         "frames' samples where they hold (reuse; docs/reuse.md), over the frames after the first. Kept: the share of the "
         "points that kept a sample. Rays: reuse's camera rays (its probes included) and every ray (shadow and bounce rays "
         "too) over the full traces'. Trace time: reuse's over the full trace's, paired frame by frame (median, min-max). "
         "Video JOD against converged frames along the path, gaze per frame (its floor a second converged path). Speedup: "
         "over full resolution at the row's spp traced from the same pose beside each pair (median, min-max), the frame "
         "being reuse's trace plus the method's reconstruction timed on the still view.\n\n"
         "| scene | gaze | configuration | spp | reuse settings | kept | camera rays | every ray | trace time | "
         "video JOD traced -> reuse | flicker traced -> reuse | speedup over full resolution |\n"
         "|---|---|---|---:|---|---:|---:|---:|---:|---|---|---:|\n" + md + "\n";
}

void write_bench_report(const std::vector<result_row>& rows, const bench_options& o, const std::string& path, int argc,
                        char** argv) {
  std::string md = "# fovbench report\n\n```\n";
  for (int i = 0; i < argc; ++i) md += (i ? " " : "") + std::string(argv[i]);
  md += "\n```\n\n";
  md += fmt::format("{} rows in `results.csv`. Every error is on display values against a converged full-resolution reference "
                    "({} Sobol rays per pixel); its noise floor is a second such reference (another seed) measured against it. "
                    "Times are medians of {} repetitions, each timing the full-resolution frame at the same spp right before the "
                    "configuration (speedups are per-repetition ratios: median, min, max). FLIP is LDR-FLIP at the display's "
                    "pixels per degree; the foveated FLIP widens its filters as acuity falls (docs/metrics.md).\n\n",
                    rows.size(), o.reference_spp, o.frames);
  // The verdicts first: one per scene, in JOD.
  md += "## Verdict (JOD: FovVideoVDP foveated at each row's gaze, means over the gazes)\n\n";
  for (const sweep_part& scene : scenes_of(rows)) {
    const std::vector<knob_mean> means = knob_means(rows_of(rows, scene));
    const jod_verdict v = verdict_in_jod(means);
    const double floor = noise_floor_jod(rows_of(rows, scene));
    md += fmt::format("**{}**: {}{}\n\n", part_title(scene), verdict_sentence(v),
                      !std::isnan(floor) ? fmt::format(" (The reference's noise floor: a second reference scores {:.2f} JOD "
                                                       "against it; no configuration can be shown better than that.)",
                                                       floor)
                                         : "");
    for (const std::string& line : v.lines) md += "- " + line + "\n";
    md += "\n";
  }
  md += "Speedups chain each configuration's per-repetition ratios to the full-resolution frame timed beside it (same spp) with "
        "the ladder's ratios of full-resolution frames at two spp timed back to back; intervals are 95 % bootstrap percentile "
        "intervals over both. The best configuration is chosen by its estimate, so its interval is optimistic when many come "
        "close.\n\n";
  // The same question asked of each scheme on its own, at one quality: the goal's.
  if (const std::vector<scheme_answer> answers = at_goal(scheme_answers_by_level(rows), goal_target_jod); !answers.empty())
    md += fmt::format("## Each scheme at the cheapest full frame reaching {:.1f} JOD\n\n", goal_target_jod) +
          scheme_answers_markdown(answers) + "\n";
  // How noisy the machine was: the timing spreads of every row.
  std::vector<const result_row*> all;
  for (const result_row& r : rows) all.push_back(&r);
  std::vector<double> rel;
  size_t noisy = 0;
  for (const result_row* r : all) {
    const double m = r->number("frame_ms");
    if (m > 0) rel.push_back((r->number("frame_ms_hi") - r->number("frame_ms_lo")) / m);
    noisy += r->text("timing_flag") == "noisy";
  }
  std::sort(rel.begin(), rel.end());
  if (!rel.empty())
    md += fmt::format("**Timing noise**: the spread (max - min) of a row's repetitions was {:.0f} % of its median at the median "
                      "row, {:.0f} % at the worst; {} of {} rows exceed the {:.0f} % limit and are flagged `noisy`.\n\n",
                      100 * rel[rel.size() / 2], 100 * rel.back(), noisy, rows.size(), 100 * o.spread_limit);
  for (const sweep_part& scene : scenes_of(rows)) {
    const std::vector<const result_row*> mine = rows_of(rows, scene);
    const std::vector<knob_mean> means = knob_means(mine);
    const std::string metric = headline_metric(means);
    md += fmt::format("## {}\n\n", part_title(scene));
    // The reference's own error and where the scene has content, per gaze.
    md += "### The reference: noise floor and content\n\n| gaze | floor JOD | floor JOD non-foveated | floor PSNR | floor PSNR < 5° | "
          "floor FLIP | floor FLIP < 5° | floor foveated FLIP | geometry < 5° | 5-10° | 10-20° | 20-30° | > 30° |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::set<std::string> gazes_seen;
    for (const result_row* r : mine) {
      if (!gazes_seen.insert(r->text("gaze")).second) continue;
      auto share = [&](const char* c) { return std::isnan(r->number(c)) ? std::string("-") : fmt::format("{:.0f} %", 100 * r->number(c)); };
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r->text("gaze"),
                        fmt_jod(r->number("noise_floor_jod")), fmt_jod(r->number("noise_floor_jod_nonfoveated")),
                        fmt_db(r->number("noise_floor_psnr")),
                        fmt_db(r->number("noise_floor_psnr_fovea")), fmt_err(r->number("noise_floor_flip")),
                        fmt_err(r->number("noise_floor_flip_fovea")), fmt_err(r->number("noise_floor_foveated_flip")),
                        share("geometry_fovea"), share("geometry_5_10"), share("geometry_10_20"), share("geometry_20_30"),
                        share("geometry_periphery"));
    }
    md += "\nAn error near the floor is the reference's, not the configuration's.\n\n";
    md += fmt::format("### Equal-error speedup over the best baseline ({})\n\n", metric);
    md += equal_error_table(means, metric);
    if (metric == "foveated_flip")
      for (const std::string other : {"foveated_flip_worst_band", "foveated_flip_p99", "flip", "flip_fovea"})
        md += fmt::format("\nPooled as `{}`:\n\n", other) + equal_error_table(means, other);
    md += fmt::format("\n### Pareto fronts ({} against frame time, means over the gazes)\n\n", metric);
    md += "| kind | configuration | frame ms (min-max) | same-spp speedup (min-max) | JOD | JOD non-foveated | PSNR | PSNR < 5° | "
          "FLIP | FLIP < 5° | foveated FLIP | worst band | foveated error |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const std::set<row_kind>& kinds : {foveated_kind, baseline_kinds})
      for (size_t i : front_of(means, kinds, metric)) {
        const knob_mean& m = means[i];
        md += fmt::format("| {} | {} | {:.1f} ({:.1f}-{:.1f}) | {:.2f} ({:.2f}-{:.2f}) | {} | {} | {} | {} | {} | {} | {} | {} | {:.4f} |\n",
                          row_kind_name(m.kind), m.label(), m.frame_ms, m.frame_lo, m.frame_hi, m.speedup, m.speedup_lo, m.speedup_hi,
                          fmt_jod(m.jod), fmt_jod(m.jod_nonfoveated), fmt_db(m.psnr), fmt_db(m.psnr_fovea), fmt_err(m.flip), fmt_err(m.flip_fovea), fmt_err(m.foveated_flip),
                          fmt_err(m.foveated_flip_worst_band), m.foveated_error);
      }
    md += fmt::format("\nTiming spread over this scene's rows (min / median / max): frame ms {}, same-spp speedup {}.\n",
                      spread_of(mine, "frame_ms", "{:.1f}"), spread_of(mine, "speedup", "{:.2f}"));
    const bool by_psnr = !std::isnan(o.budget_psnr), by_foveated = !std::isnan(o.budget_foveated);
    if (by_psnr || by_foveated) {
      const knob_mean* fastest = nullptr;
      for (const knob_mean& m : means) {
        const bool ok = by_psnr ? m.psnr >= o.budget_psnr : m.foveated_error <= o.budget_foveated;
        if (ok && (!fastest || m.frame_ms < fastest->frame_ms)) fastest = &m;
      }
      const std::string budget = by_psnr ? fmt::format("PSNR >= {} dB", o.budget_psnr)
                                         : fmt::format("foveated error <= {}", o.budget_foveated);
      md += fastest ? fmt::format("\n**Fastest within the budget ({}, means over the gazes)**: {} ({}): {:.1f} ms, "
                                  "{:.2f}x full resolution at its spp, PSNR {} dB, foveated error {:.4f}.\n",
                                  budget, fastest->label(), row_kind_name(fastest->kind), fastest->frame_ms, fastest->speedup,
                                  fmt_db(fastest->psnr), fastest->foveated_error)
                    : fmt::format("\n**No configuration meets the budget ({}).**\n", budget);
    }
    // Beside the thesis: its 4.3x at s = 1.0 came from a sample ratio, not a time.
    md += "\n### Against the thesis's claims (same-spp speedups)\n\n| scale | method | k | spp | rays / full-resolution rays | "
          "measured speedup (min-max) | PSNR |\n|---:|---|---:|---:|---:|---:|---:|\n";
    for (const result_row* r : mine) {
      if (r->kind() != row_kind::foveated || r->text("gaze") != mine[0]->text("gaze") || r->text("density") == "adaptive")
        continue;
      const double s = r->number("scale");
      if (std::fabs(s - 1.0) > 1e-6 && std::fabs(s - 1.75) > 1e-6) continue;
      md += fmt::format("| {} | {} | {} | {} | {:.3f} | {:.2f} ({:.2f}-{:.2f}) | {} |\n", r->text("scale"), r->text("method"),
                        r->text("k"), r->text("spp"), r->number("rays") / r->number("full_rays"), r->number("speedup"),
                        r->number("speedup_lo"), r->number("speedup_hi"), fmt_db(r->number("psnr")));
    }
    md += "\nThe thesis claimed a 4.3x speedup at s = 1.0 from a sample ratio of 22.8 % (1 / ratio), and a mean "
          "detection threshold near s = 1.75 with no difference between methods.\n\n";
  }
  md += reuse_markdown(rows);
  md += "Figures (PNG and SVG): `pareto_jod` (JOD), `pareto` (foveated FLIP), `pareto_flip` (FLIP), `error_by_eccentricity`, "
        "`speedup_vs_scale`.\n";
  write_file_atomic(path, md.data(), md.size());
}

}  // namespace fov
