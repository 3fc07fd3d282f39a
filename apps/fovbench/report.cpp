#include "report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "fov/pointset_io.h"
#include "plot.h"

namespace fov {

namespace {

int method_colour(const std::string& m) { return m == "nn" ? 0 : m == "shepard" ? 1 : 2; }

std::vector<std::string> scenes_of(const std::vector<result_row>& rows) {
  std::vector<std::string> out;
  for (const result_row& r : rows)
    if (std::find(out.begin(), out.end(), r.text("scene")) == out.end()) out.push_back(r.text("scene"));
  return out;
}


std::string short_scene(const std::string& s) {
  const std::string name = std::filesystem::path(s.substr(s.rfind(':') == std::string::npos ? 0 : s.rfind(':') + 1)).filename().string();
  return s.rfind("env:", 0) == 0 ? "env:" + name : name;
}

// A configuration of knobs (scale, method, k, spp) averaged over the gazes of the sweep:
// the gaze is not a knob, so the trade is judged on the average. Its errors are against
// the reference with the most rays per pixel, so configurations of different spp are
// judged against one target.
struct knob_mean {
  std::string method, k, scale, spp;
  double frame_ms = 0, reference_ms = 0, foveated_error = 0, psnr = 0, psnr_fovea = 0, speedup = 0;
  int gazes = 0;
};

std::vector<knob_mean> knob_means(const std::vector<const result_row*>& rows) {
  std::vector<knob_mean> out;
  for (const result_row* r : rows) {
    auto it = std::find_if(out.begin(), out.end(), [&](const knob_mean& m) {
      return m.method == r->text("method") && m.k == r->text("k") && m.scale == r->text("scale") && m.spp == r->text("spp");
    });
    if (it == out.end()) it = out.insert(out.end(), knob_mean{r->text("method"), r->text("k"), r->text("scale"), r->text("spp")});
    it->frame_ms += r->number("frame_ms"), it->reference_ms += r->number("reference_ms");
    // PSNRs are averaged as mean squared errors (an identical band, PSNR inf, adds 0).
    auto mse = [](double psnr) { return 255.0 * 255.0 / std::pow(10.0, psnr / 10); };
    it->foveated_error += r->number("foveated_error_vs_best"), it->psnr += mse(r->number("psnr_vs_best_reference"));
    it->psnr_fovea += mse(r->number("psnr_fovea")), it->speedup += r->number("speedup"), ++it->gazes;
  }
  for (knob_mean& m : out) {
    const double n = m.gazes;
    m.frame_ms /= n, m.reference_ms /= n, m.foveated_error /= n, m.speedup /= n;
    auto psnr = [](double mse) { return mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : INFINITY; };
    m.psnr = psnr(m.psnr / n), m.psnr_fovea = psnr(m.psnr_fovea / n);
  }
  return out;
}

std::vector<size_t> front_of(const std::vector<knob_mean>& means) {
  std::vector<double> x, y;
  for (const knob_mean& m : means) x.push_back(m.frame_ms), y.push_back(m.foveated_error);
  return pareto_front(x, y);
}

}  // namespace

void write_bench_figures(const std::vector<result_row>& rows, const bench_options& o, const std::string& dir) {
  std::vector<plot_panel> pareto, profiles, speedups;
  for (const std::string& scene : scenes_of(rows)) {
    std::vector<const result_row*> mine;
    for (const result_row& r : rows)
      if (r.text("scene") == scene) mine.push_back(&r);
    const std::vector<knob_mean> means = knob_means(mine);
    const std::vector<size_t> front = front_of(means);
    // Pareto: foveated error against frame time (means over the gazes), one colour per
    // method, the front ringed, joined and labelled (scale, spp, k).
    plot_panel p;
    p.title = "Pareto front: " + short_scene(scene) + " (mean over gazes)";
    p.x_label = "frame time (ms, log scale)";
    p.y_label = "foveated error vs best reference";
    p.log_x = true;
    for (const std::string m : {"nn", "shepard", "rbf"}) {
      plot_series s;
      s.name = m;
      s.colour = method_colour(m);
      s.lines = false;
      for (size_t i = 0; i < means.size(); ++i)
        if (means[i].method == m) {
          s.x.push_back(means[i].frame_ms);
          s.y.push_back(means[i].foveated_error);
          const bool on_front = std::find(front.begin(), front.end(), i) != front.end();
          s.ringed.push_back(on_front);
          // The front's points say what they are: scale, rays per sample and k.
          s.labels.push_back(on_front ? fmt::format("s{} {}spp{}", means[i].scale, means[i].spp,
                                                    m == std::string("nn") ? "" : " k" + means[i].k)
                                      : "");
        }
      if (!s.x.empty()) p.series.push_back(s);
    }
    plot_series f;
    f.name = "Pareto front";
    f.colour = 6;
    f.markers = false;
    for (size_t i : front) f.x.push_back(means[i].frame_ms), f.y.push_back(means[i].foveated_error);
    p.series.push_back(f);
    pareto.push_back(p);

    // Error by eccentricity: each method at the smallest and largest scale, at the first
    // gaze, the most rays per sample and the first k listed (nn: 1).
    plot_panel e;
    const std::string gaze = mine.empty() ? "" : mine[0]->text("gaze");
    double lo_scale = 1e9, hi_scale = 0, top_spp = 0;
    for (const result_row* r : mine)
      lo_scale = std::min(lo_scale, r->number("scale")), hi_scale = std::max(hi_scale, r->number("scale")),
      top_spp = std::max(top_spp, r->number("spp"));
    e.title = fmt::format("Error by eccentricity: {} (gaze {}, {:g} spp)", short_scene(scene), gaze, top_spp);
    e.x_label = "eccentricity (degrees)";
    e.y_label = "RMSE (full scale)";
    std::set<std::string> drawn;
    for (const result_row* r : mine) {
      const double s = r->number("scale");
      if (r->text("gaze") != gaze || r->number("spp") != top_spp || (s != lo_scale && s != hi_scale)) continue;
      const std::string id = r->text("method") + "|" + r->text("scale");
      if (drawn.count(id) || (r->text("method") != "nn" && r->text("k") != std::to_string(o.ks.empty() ? 5 : o.ks[0])))
        continue;
      drawn.insert(id);
      plot_series line;
      line.name = fmt::format("{} k={} s={}", r->text("method"), r->text("k"), r->text("scale"));
      line.colour = method_colour(r->text("method")) + (s == hi_scale && s != lo_scale ? 3 : 0);
      line.markers = false;
      std::stringstream in(r->text("error_profile"));
      std::string v;
      for (int bin = 0; std::getline(in, v, ';'); ++bin) line.x.push_back((bin + 0.5) * 2.5), line.y.push_back(std::stod(v));
      e.series.push_back(line);
    }
    profiles.push_back(e);

    // Speedup against scale: per method (at the first k listed; nn at 1) and spp, averaged over gazes.
    plot_panel sp;
    sp.title = "Speedup over the reference: " + short_scene(scene) + " (mean over gazes)";
    sp.x_label = "point-set scale s";
    sp.y_label = "speedup (reference ms / frame ms)";
    const std::string first_k = std::to_string(o.ks.empty() ? 5 : o.ks[0]);
    std::map<std::string, std::map<double, std::pair<double, int>>> curves;
    for (const result_row* r : mine) {
      if (r->text("method") != "nn" && r->text("k") != first_k) continue;
      auto& cell = curves[fmt::format("{} k={} spp={:>2}", r->text("method"), r->text("k"), r->text("spp"))][r->number("scale")];
      cell.first += r->number("speedup"), ++cell.second;
    }
    int c = 0;
    for (const auto& [name, points] : curves) {
      if (sp.series.size() >= 9) break;
      plot_series s;
      s.name = name;
      s.colour = c++;
      for (const auto& [scale, sum] : points) s.x.push_back(scale), s.y.push_back(sum.first / sum.second);
      sp.series.push_back(s);
    }
    speedups.push_back(sp);
  }
  write_plot(pareto, dir + "/pareto.png");
  write_plot(profiles, dir + "/error_by_eccentricity.png");
  write_plot(speedups, dir + "/speedup_vs_scale.png");
}

void write_bench_report(const std::vector<result_row>& rows, const bench_options& o, const std::string& path, int argc,
                        char** argv) {
  std::string md = "# fovbench report\n\n```\n";
  for (int i = 0; i < argc; ++i) md += (i ? " " : "") + std::string(argv[i]);
  md += "\n```\n\n";
  md += fmt::format("{} configurations in `results.csv`. Times are medians of {} frames (trace and reconstruction "
                    "timed apart and added; the reference timed the same way in the same run). Errors are on "
                    "display values against the full-resolution reference with the same rays per pixel; the "
                    "foveated error weights each pixel's squared error by the eye's cut-off frequency at its "
                    "eccentricity relative to the display's (docs/speed-accuracy.md).\n\n",
                    rows.size(), o.frames);
  for (const std::string& scene : scenes_of(rows)) {
    std::vector<const result_row*> mine;
    for (const result_row& r : rows)
      if (r.text("scene") == scene) mine.push_back(&r);
    md += fmt::format("## {}\n\n### Pareto front (frame time against foveated error, means over the gazes)\n\n",
                      short_scene(scene));
    md += "| method | k | scale | spp | frame ms | reference ms | speedup | PSNR* | PSNR < 5° | foveated error* |\n";
    md += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    const std::vector<knob_mean> means = knob_means(mine);
    for (size_t i : front_of(means)) {
      const knob_mean& m = means[i];
      md += fmt::format("| {} | {} | {} | {} | {:.1f} | {:.1f} | {:.2f} | {:.2f} | {:.2f} | {:.4f} |\n", m.method, m.k, m.scale,
                        m.spp, m.frame_ms, m.reference_ms, m.speedup, m.psnr, m.psnr_fovea, m.foveated_error);
    }
    md += "\n\\* against the reference with the most rays per pixel (the others: the reference with the same spp; "
          "speedup: against that reference's time).\n";
    const bool by_psnr = !std::isnan(o.budget_psnr), by_foveated = !std::isnan(o.budget_foveated);
    if (by_psnr || by_foveated) {
      const knob_mean* fastest = nullptr;
      for (const knob_mean& m : means) {
        const bool ok = by_psnr ? m.psnr >= o.budget_psnr : m.foveated_error <= o.budget_foveated;
        if (ok && (!fastest || m.frame_ms < fastest->frame_ms)) fastest = &m;
      }
      const std::string budget = by_psnr ? fmt::format("PSNR* >= {} dB", o.budget_psnr)
                                         : fmt::format("foveated error* <= {}", o.budget_foveated);
      md += fastest ? fmt::format("\n**Fastest within the budget ({}, means over the gazes)**: {} k={} s={} spp={}: {:.1f} ms, "
                                  "{:.2f}x the reference, PSNR {:.2f} dB, foveated error {:.4f}.\n",
                                  budget, fastest->method, fastest->k, fastest->scale, fastest->spp, fastest->frame_ms,
                                  fastest->speedup, fastest->psnr, fastest->foveated_error)
                    : fmt::format("\n**No configuration meets the budget ({}).**\n", budget);
    }
    // Beside the thesis: its 4.3x at s = 1.0 came from a sample ratio, not a time.
    md += "\n### Against the thesis's claims\n\n| scale | method | k | spp | rays / reference rays | measured speedup | PSNR |\n"
          "|---:|---|---:|---:|---:|---:|---:|\n";
    for (const result_row* r : mine) {
      if (r->text("gaze") != mine[0]->text("gaze")) continue;
      const double s = r->number("scale");
      if (std::fabs(s - 1.0) > 1e-6 && std::fabs(s - 1.75) > 1e-6) continue;
      md += fmt::format("| {} | {} | {} | {} | {:.3f} | {:.2f} | {:.2f} |\n", r->text("scale"), r->text("method"), r->text("k"),
                        r->text("spp"), r->number("rays") / r->number("reference_rays"), r->number("speedup"), r->number("psnr"));
    }
    md += "\nThe thesis claimed a 4.3x speedup at s = 1.0 from a sample ratio of 22.8 % (1 / ratio), and a mean "
          "detection threshold near s = 1.75 with no difference between methods.\n\n";
  }
  md += "Figures: `pareto.png`, `error_by_eccentricity.png`, `speedup_vs_scale.png`.\n";
  write_file_atomic(path, md.data(), md.size());
}

}  // namespace fov
