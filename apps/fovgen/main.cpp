// fovgen: generates, inspects and plots foveated point sets (thesis Sec. 4.1).
#include <CLI/CLI.hpp>

#include "../common/cli.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"fovgen: foveated Poisson-disc point sets with k-NN tables (thesis Sec. 4.1)"};
  app.set_help_all_flag("--help-all");
  fov::generate_options gen;
  fov::add_generate_flags(app, gen);
  app.add_option("--scale,-s", gen.scale, "Eccentricity scale s (thesis 1.0 .. 3.0); larger is sparser");
  app.add_option("-o,--output", gen.output, "Output .fovset file");
  app.add_option("--levels", gen.levels,
                 "A nested set: scales S1,S2,... increasing (finest first, e.g. 0.7,1.0,1.5,2.25,3.0); the points of "
                 "the coarsest levels down to each scale form a Poisson-disc set at it (docs/adaptive.md)")
      ->delimiter(',')
      ->expected(1, int(fov::max_levels));

  CLI::App* info = app.add_subcommand("info", "Describe a point-set file");
  fov::info_options io;
  info->add_option("file", io.file, "Point-set file")->required();
  info->add_option("--gaze", io.gaze, "X,Y in screen pixels (or centre, corner): count the points to trace");
  info->add_option("--k", io.k, "Neighbours the renderer reads (default: all stored)")->check(CLI::Range(1u, fov::max_knn));
  info->add_flag("--json", io.json, "Print JSON");

  CLI::App* plot = app.add_subcommand("plot", "Draw every point of a set (thesis Fig. 12)");
  fov::plot_options po;
  plot->add_option("file", po.file, "Point-set file")->required();
  plot->add_option("-o,--output", po.output, "Output PNG")->required();
  plot->add_option("--gaze", po.gaze, "Outline the screen for this gaze and colour the traced points");
  plot->add_option("--k", po.k, "Neighbours the renderer reads (default: all stored)")->check(CLI::Range(1u, fov::max_knn));

  CLI::App* sweep = app.add_subcommand("sweep", "Generate a family of sets over scales (the staircase)");
  fov::sweep_options so;
  fov::add_generate_flags(*sweep, so.generate);
  sweep->add_option("--scales", so.scales, "START:END:STEP or a comma list");
  sweep->add_option("-o,--output", so.dir, "Output directory")->required();
  sweep->add_flag("--skip-existing", so.skip_existing, "Keep sets already in the directory that load cleanly");

  CLI::App* displays = app.add_subcommand("displays", "List the preset displays with their geometry (docs/displays.md)");
  bool displays_json = false;
  std::string display_spec;
  displays->add_option("--display", display_spec, "Describe this display instead: " + fov::display_help());
  displays->add_flag("--json", displays_json, "Print JSON");

  CLI::App* acuity = app.add_subcommand("acuity", "Tabulate (and plot) every acuity model's spacing against eccentricity");
  fov::acuity_options ao;
  acuity->add_option("--display", ao.display, "Display: " + fov::display_help());
  acuity->add_option("--scale,-s", ao.scale, "Eccentricity scale s");
  acuity->add_option("-o,--output", ao.output, "Figure stem: writes STEM.png and STEM.svg");
  acuity->add_flag("--json", ao.json, "Print JSON instead of CSV");

  return fov::run_tool("fovgen", app, argc, argv, [&] {
    if (*acuity) return fov::run_acuity(ao);
    if (*info) return fov::run_info(io);
    if (*displays) return fov::run_displays(display_spec, displays_json);
    if (*plot) return fov::run_plot(po);
    if (*sweep) {
      fov::note_given_flags(*sweep, so.generate);
      return fov::run_sweep(so);
    }
    fov::note_given_flags(app, gen);
    gen.scale_given = app.count("--scale") > 0;
    return fov::run_generate(gen);
  });
}
