#include "yardstick.h"

#include <cmath>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "fov/files.h"
#include "fov/flicker.h"
#include "fov/reconstruct_params.h"
#include "fov/scene.h"
#include "fov/usage_error.h"
#include "plot.h"

namespace fov {

namespace fs = std::filesystem;

double thesis_threshold(const std::string& method) {
  if (method == "nn") return 1.751;
  if (method == "shepard") return 1.779;
  if (method == "rbf") return 1.675;
  return NAN;
}

double scale_at_jod(const std::vector<double>& scales, const std::vector<double>& jod, double level) {
  if (scales.empty() || !(jod[0] > level)) return NAN;
  for (size_t i = 1; i < scales.size(); ++i)
    if (jod[i] <= level) return scales[i - 1] + (scales[i] - scales[i - 1]) * (jod[i - 1] - level) / (jod[i - 1] - jod[i]);
  return NAN;
}

namespace {

std::string csv_of(const std::vector<yardstick_row>& rows) {
  std::string out =
      "scene,gaze,path,scale,method,k,spp,frames,jod_taa,jod_taa_nonfoveated,jod_raw,jod_raw_nonfoveated,flicker_raw,flicker_taa\n";
  for (const yardstick_row& r : rows)
    out += fmt::format("{},{},{},{:.2f},{},{},{},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.6f},{:.6f}\n", csv_cell(r.scene), r.gaze, r.path,
                       r.scale, r.method, r.k, r.spp, r.taa.frames, r.taa.jod, r.taa.jod_nonfoveated, r.raw.jod,
                       r.raw.jod_nonfoveated, r.flicker_raw, r.flicker_taa);
  return out;
}

// Rows of one scene, gaze, path and method, by scale.
std::vector<const yardstick_row*> curve(const std::vector<yardstick_row>& rows, const yardstick_row& like) {
  std::vector<const yardstick_row*> out;
  for (const yardstick_row& r : rows)
    if (r.scene == like.scene && r.gaze == like.gaze && r.path == like.path && r.method == like.method && r.spp == like.spp)
      out.push_back(&r);
  return out;
}

}  // namespace

std::vector<yardstick_row> run_yardstick(const bench_options& o, const bench_reporter& report) {
  const display_geometry display = check_bench_options(o);
  if (o.temporal_frames < 2) throw usage_error("--yardstick needs --temporal-frames 2..200 (the frames of each path)");
  if (!o.jod) throw usage_error("--yardstick measures JOD: drop --no-jod");
  const std::vector<named_gaze> gazes = parse_gazes(o.gazes, display, o.render.seed);
  make_output_dir(o.out);
  const uint32_t k = o.ks.empty() ? 5 : o.ks[0];
  std::vector<yardstick_row> rows;
  flicker_params moving;
  moving.frames = o.temporal_frames, moving.fps = o.temporal_fps, moving.photometry = o.photometry;
  moving.full_resolution = false;
  moving.taa_own_rays = true;  // TAA as a viewer sees it: the pattern moves every frame
  flicker_params still = moving;
  still.yaw_deg_per_frame = 0, still.gaze_px_per_frame = 0;
  auto say = [&](const std::string& what) { report.progress(rows.size(), 0, what); };
  for (const std::string& scene_name : o.scenes) {
    std::shared_ptr<const scene> scn = load_scene(scene_name, o.render.env_light);
    renderer r(scn, o.render);
    r.warm_up_reference(display.width, display.height, o.render);
    for (uint32_t spp : o.spps) {
      render_params p = o.render;
      p.spp = spp;
      p.taa = true;
      // The non-foveated frames with the same rays per pixel along both paths (a set must be
      // in use for the display: the first scale's).
      r.use_pointset(bench_pointset(o, display, o.scales[0], say));
      report.line(fmt::format("{}: full-resolution frames at {} spp along both paths", scene_name, spp));
      const std::vector<frame> full_still = converged_path(r, p, spp, p.seed, still), full_moving = converged_path(r, p, spp, p.seed, moving);
      for (double scale : o.scales) {
        r.use_pointset(bench_pointset(o, display, scale, say));
        for (method m : o.methods)
          for (const named_gaze& g : gazes)
            for (const auto& [path, fp, full] : {std::tuple<const char*, const flicker_params&, const std::vector<frame>&>{
                                                     "still", still, full_still},
                                                 {"moving", moving, full_moving}}) {
              p.reconstruct.how = m;
              p.reconstruct.k = m == method::nn ? 1 : k;
              say(fmt::format("{} s={:.2f} {} {} {}", scene_name, scale, method_name(m), g.name, path));
              const flicker_report fl = measure_flicker(r, g.at, p, fp, full);
              yardstick_row row;
              row.scene = scene_name, row.gaze = g.name, row.path = path, row.scale = scale, row.method = method_name(m);
              row.k = p.reconstruct.k, row.spp = spp, row.taa = fl.jod_taa, row.raw = fl.jod_raw;
              row.flicker_raw = fl.raw, row.flicker_taa = fl.taa;
              rows.push_back(row);
            }
      }
    }
  }
  const std::string csv = csv_of(rows);
  write_file_atomic((fs::path(o.out) / "yardstick.csv").string(), csv.data(), csv.size());

  // The figure: JOD (TAA, foveated) against scale, a panel per scene and gaze; colour by
  // method, solid still, dashed moving; the observers' thresholds dotted.
  std::vector<plot_panel> panels;
  std::string md = fmt::format(
      "# The thesis's observers as a yardstick for JOD\n\nFovVideoVDP (foveated at the gaze; non-foveated in brackets) of the "
      "foveated frames through TAA against the full-resolution frames with the same {} rays per pixel, over {} frames at {:g} "
      "frames per second, the view still or turning (the temporal path). 10 means no visible difference; observers saw "
      "foveation at s = 1.751 (nn), 1.779 (shepard), 1.675 (rbf) (thesis Table 5). The last column is the scale at which JOD "
      "first falls to 9 (1 JOD: 75 % of observers would prefer the non-foveated frame), interpolated.\n\n",
      o.spps.empty() ? 0 : o.spps[0], o.temporal_frames, o.temporal_fps);
  std::set<std::string> drawn;  // scene|gaze|spp
  for (const yardstick_row& first : rows) {
    if (!drawn.insert(fmt::format("{}|{}|{}", first.scene, first.gaze, first.spp)).second) continue;
    plot_panel panel;
    panel.title = fmt::format("JOD against scale: {}, gaze {}, {} spp", short_scene(first.scene), first.gaze, first.spp);
    panel.x_label = "point-set scale s";
    panel.y_label = "JOD vs full resolution, same rays (TAA)";
    md += fmt::format("## {}, gaze {}, {} spp\n\n| path | method | ", first.scene, first.gaze, first.spp);
    std::vector<double> scales;
    for (const yardstick_row* r : curve(rows, first)) scales.push_back(r->scale);
    for (double s : scales) md += fmt::format("s = {:.2f} | ", s);
    md += "JOD 9 at s | observers |\n|---|---|";
    for (size_t i = 0; i < scales.size(); ++i) md += "---:|";
    md += "---:|---:|\n";
    for (const char* path : {"still", "moving"})
      for (method m : o.methods) {
        yardstick_row like = first;
        like.path = path, like.method = method_name(m);
        const std::vector<const yardstick_row*> c = curve(rows, like);
        if (c.empty()) continue;
        plot_series s;
        s.name = fmt::format("{} {}", like.method, path);
        s.scheme = like.method, s.style = std::string(path) == "still" ? "solid" : "dashed";
        std::vector<double> x, y;
        md += fmt::format("| {} | {} | ", path, like.method);
        for (const yardstick_row* r : c) {
          x.push_back(r->scale), y.push_back(r->taa.jod);
          md += fmt::format("{:.2f} ({:.2f}) | ", r->taa.jod, r->taa.jod_nonfoveated);
        }
        s.x = x, s.y = y;
        panel.series.push_back(s);
        const double at9 = scale_at_jod(x, y, 9.0);
        md += fmt::format("{} | {:.3f} |\n", std::isnan(at9) ? std::string("-") : fmt::format("{:.2f}", at9),
                          thesis_threshold(like.method));
      }
    for (method m : o.methods) {
      plot_series t;
      t.name = fmt::format("observers' threshold, {}", method_name(m));
      t.scheme = method_name(m), t.style = "dotted", t.markers = false;
      double lo = 10, hi = 0;
      for (const plot_series& s : panel.series)
        for (double v : s.y) lo = std::min(lo, v), hi = std::max(hi, v);
      t.x = {thesis_threshold(t.scheme), thesis_threshold(t.scheme)}, t.y = {lo, std::max(hi, 9.0)};
      panel.series.push_back(t);
    }
    plot_series nine;
    nine.name = "1 JOD below no difference";
    nine.scheme = "front-foveated", nine.style = "dotted", nine.markers = false;
    nine.x = {o.scales.front(), o.scales.back()}, nine.y = {9, 9};
    panel.series.push_back(nine);
    panels.push_back(panel);
    md += "\n";
  }
  md += "Figure: `yardstick_jod.png` / `.svg`. Data: `yardstick.csv` (also the raw sequences' JOD and the flicker of both).\n";
  write_file_atomic((fs::path(o.out) / "yardstick.md").string(), md.data(), md.size());
  if (const std::string why = write_plot(panels, (fs::path(o.out) / "yardstick_jod").string()); !why.empty())
    report.line("warning: " + why);
  return rows;
}

}  // namespace fov
