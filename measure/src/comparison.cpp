#include "fov/comparison.h"

#include <fmt/format.h>

namespace fov {

using json = nlohmann::json;

comparison compare_images(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                          const comparison_params& p) {
  comparison c;
  c.error = measure_error(test, reference, eye, gaze);
  c.geometry = geometry_coverage(reference, eye.display, gaze, c.error.edges_deg);
  if (p.flip) c.flip = measure_flip(test, reference, eye, gaze, c.error.edges_deg, p.keep_maps), c.has_flip = true;
  if (p.jod && test.width >= 8 && test.height >= 8) {
    display_geometry d = eye.display;
    d.width = test.width, d.height = test.height;
    c.jod = fvvdp_image(test, reference, d, gaze, p.photometry), c.has_jod = true;
  }
  return c;
}

namespace {

std::string band_name(const std::vector<double>& edges, size_t b) {
  if (b == 0) return fmt::format("<{:g}", edges[0]);
  if (b == edges.size()) return fmt::format(">{:g}", edges.back());
  return fmt::format("{:g}-{:g}", edges[b - 1], edges[b]);
}

json number_or_null(double v) { return std::isnan(v) ? json(nullptr) : json(v); }

// Bands [from, to) of the report merged into one: pixel-weighted mean squared error and SSIM.
band_metrics merge(const error_report& e, size_t from, size_t to) {
  band_metrics m;
  double squared = 0, ssim = 0;
  for (size_t b = from; b < to; ++b) {
    const band_metrics& x = e.bands[b];
    if (!x.pixels) continue;
    squared += double(x.pixels) * (std::isfinite(x.psnr) ? 255.0 * 255.0 / std::pow(10.0, x.psnr / 10) : 0.0);
    ssim += double(x.pixels) * x.ssim;
    m.pixels += x.pixels;
  }
  if (!m.pixels) return m;
  m.psnr = squared > 0 ? 10 * std::log10(255.0 * 255.0 * double(m.pixels) / squared) : INFINITY;
  m.ssim = ssim / double(m.pixels);
  return m;
}

}  // namespace

json comparison_json(const comparison& c) {
  const error_report& e = c.error;
  const band_metrics mid = merge(e, 1, e.bands.size() - 1), periphery = merge(e, e.bands.size() - 1, e.bands.size());
  json bands = json::array();
  for (size_t b = 0; b < e.bands.size(); ++b) {
    json band{{"band", band_name(e.edges_deg, b)},
              {"from_deg", b == 0 ? 0.0 : e.edges_deg[b - 1]},
              {"to_deg", b == e.edges_deg.size() ? json(nullptr) : json(e.edges_deg[b])},
              {"pixels", e.bands[b].pixels},
              {"psnr", db_json(e.bands[b].psnr)},
              {"ssim", e.bands[b].pixels ? json(e.bands[b].ssim) : json(nullptr)}};
    band["geometry"] = number_or_null(c.geometry[b]);  // null: the reference has no depth (not an EXR of ours)
    if (c.has_flip) band["flip"] = number_or_null(c.flip.flip.bands[b]), band["foveated_flip"] = number_or_null(c.flip.foveated.bands[b]);
    bands.push_back(band);
  }
  json j{{"psnr", db_json(e.overall.psnr)},
         {"ssim", e.overall.ssim},
         {"psnr_fovea", db_json(e.bands[0].psnr)},
         {"ssim_fovea", e.bands[0].ssim},
         // The thesis's three bands: < 5, 5-30, > 30 degrees.
         {"psnr_mid", db_json(mid.psnr)},
         {"ssim_mid", mid.pixels ? json(mid.ssim) : json(nullptr)},
         {"psnr_periphery", db_json(periphery.psnr)},
         {"ssim_periphery", periphery.pixels ? json(periphery.ssim) : json(nullptr)},
         {"foveated_error", e.foveated_error},
         {"foveated_psnr", db_json(e.foveated_psnr)},
         {"bands", bands}};
  if (c.has_jod) j["jod"] = c.jod.jod, j["jod_nonfoveated"] = c.jod.jod_nonfoveated;
  if (c.has_flip) {
    j["ppd"] = c.flip.ppd;
    j["flip"] = c.flip.flip.mean;
    j["flip_fovea"] = number_or_null(c.flip.flip.bands[0]);
    j["flip_p99"] = c.flip.flip.p99;
    j["foveated_flip"] = c.flip.foveated.mean;
    j["foveated_flip_p99"] = c.flip.foveated.p99;
    j["foveated_flip_worst_band"] = c.flip.foveated.worst_band;
  }
  return j;
}

std::string comparison_text(const comparison& c, const std::string& against) {
  auto db = [](double v) { return std::isfinite(v) ? fmt::format("{:.2f}", v) : std::string("identical"); };
  const error_report& e = c.error;
  std::string s;
  if (c.has_jod)
    s = fmt::format("vs {}: JOD {:.3f} foveated at the gaze, {:.3f} non-foveated (FovVideoVDP: 10 = no visible "
                    "difference, 1 JOD apart = 75 % of observers prefer the better)\n",
                    against, c.jod.jod, c.jod.jod_nonfoveated);
  s += fmt::format("vs {}: PSNR {} dB, SSIM {:.4f}, foveated PSNR {} dB |", against, db(e.overall.psnr),
                   e.overall.ssim, db(e.foveated_psnr));
  for (size_t b = 0; b < e.bands.size(); ++b)
    if (e.bands[b].pixels)
      s += fmt::format(" {} deg {} dB {:.4f}", band_name(e.edges_deg, b), db(e.bands[b].psnr), e.bands[b].ssim);
  if (c.has_flip) {
    s += fmt::format("\nFLIP at {:.1f} ppd: mean {:.4f}, p99 {:.4f} | foveated FLIP: mean {:.4f}, p99 {:.4f}, worst band {:.4f} |",
                     c.flip.ppd, c.flip.flip.mean, c.flip.flip.p99, c.flip.foveated.mean, c.flip.foveated.p99,
                     c.flip.foveated.worst_band);
    for (size_t b = 0; b < e.bands.size(); ++b)
      if (e.bands[b].pixels)
        s += fmt::format(" {} deg {:.4f}/{:.4f}", band_name(e.edges_deg, b), c.flip.flip.bands[b], c.flip.foveated.bands[b]);
  }
  return s;
}


converged_comparison compare_converged(renderer& r, const frame& image, const spacing_model& eye, gaze_point gaze,
                                       const render_params& p, uint32_t spp, const comparison_params& what) {
  const auto [seed_a, seed_b] = converged_seeds(p.seed);
  render_params q = p;
  q.spp = spp;
  q.reference_sampler = pixel_sampler::sobol;
  q.seed = seed_a;
  frame_timing t;
  const frame truth = r.reference(image.width, image.height, q, &t).image;
  q.seed = seed_b;
  const frame second = r.reference(image.width, image.height, q).image;
  converged_comparison c;
  c.reference_ms = t.trace_ms;
  c.against = compare_images(image, truth, eye, gaze, what);
  comparison_params floor = what;
  floor.keep_maps = false;
  c.floor = compare_images(second, truth, eye, gaze, floor);
  return c;
}

}  // namespace fov
