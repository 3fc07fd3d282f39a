// fovview: the gaze-contingent viewer. Foveated rendering follows the gaze live; keys switch
// methods and settings; an overlay shows what each costs.

#include <filesystem>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "../common/cli.h"
#include "../common/image_io.h"
#include "../common/render_flags.h"
#include "fov/pointset_io.h"
#include "viewer.h"

int main(int argc, char** argv) {
  fov::keep_frame_buffers_in_heap();
  CLI::App app{"fovview: gaze-contingent foveated rendering in a window"};
  fov::viewer_options o;
  fov::render_params settings;
  settings.spp = 4;  // live: the most --target-fps may use
  settings.taa = true;
  std::vector<std::string> screenshot_at;
  app.add_option("--scene", o.scene, "builtin, builtin:cornell (a room where bounces matter), a glTF/OBJ file, or env:IMAGE");
  app.add_option("--points", o.points, "A point set (.fovset)");
  app.add_option("--points-dir", o.points_dir, "A family of point sets to switch between with [ and ]");
  app.add_option("--scale", o.scale, "With --points-dir: the scale to start at (default the smallest)");
  app.add_option("--display", o.display, "With --points-dir holding several displays' sets: whose to show. " + fov::display_help());
  fov::add_render_flags(app, settings, fov::flags_all | fov::flags_reuse | fov::flags_stereo);
  app.add_option("--target-fps", o.target_fps, "Adapt rays per point to keep this frame rate (0: off, the default)");
  app.add_flag("--no-taa", o.no_taa, "Start with TAA off");
  app.add_flag("--pipeline", o.pipeline,
               "Trace the next frame while showing this one (more latency; pays where tracing and reconstruction "
               "use different processors)");
  fov::add_gaze_flags(app, o.gaze);
  app.add_option("--gaze-log", o.gaze_log, "Write the gaze each frame used, with its times and state, to this CSV");
  app.add_option("--gaze", o.fixed_gaze, "A fixed gaze X,Y|centre|corner (default: the mouse)");
  app.add_option("--gaze-replay", o.gaze_replay, "Replay a --gaze-log frame for frame: each frame's gaze, state and time");
  app.add_option("--camera-path", o.camera_path, "Replay a camera path (CSV t_ms,x,y,z,tx,ty,tz)");
  app.add_option("--frames", o.frames, "Stop after N frames (0: run until Q)");
  app.add_option("--screenshot-at", screenshot_at, "FRAME FILE: save frame FRAME (from 0) to FILE (.png) with FILE.json")->expected(2);
  app.add_option("--screenshot-dir", o.screenshot_dir, "Where the S key saves screenshots (default .)");
  app.add_option("--compare", o.compare, "A reference image: screenshots' JSON gets PSNR/SSIM by band against it");
  app.add_flag("--exit", o.exit_after, "Exit after --frames without waiting (for scripts and tests)");
  app.add_flag("--json", o.json, "At exit, print frame-time statistics as JSON (after 5 warm-up frames)");

  return fov::run_tool("fovview", app, argc, argv, [&]() -> int {
    using fov::usage_error;
    fov::require_valid(settings);
    if (o.points.empty() == o.points_dir.empty()) throw usage_error("give --points SET or --points-dir DIR");
    if (settings.adaptive.enabled && o.points.empty())
      throw usage_error("--adaptive refines one nested set: give --points SET (fovgen --levels), not --points-dir");
    if (!o.display.empty() && o.points_dir.empty()) throw usage_error("--display chooses among --points-dir's sets; --points names one");
    fov::require_valid(o.gaze);
    if (settings.stereo.enabled && o.pipeline) throw usage_error("--stereo does not take --pipeline yet");
    if (settings.stereo.enabled && !o.compare.empty())
      throw usage_error("--compare: a reference of one eye's screen; --stereo shows two");
    if (o.gaze.sources() + !o.fixed_gaze.empty() + !o.gaze_replay.empty() > 1) throw usage_error("choose one gaze source");
    if (!o.gaze_replay.empty() && o.target_fps > 0)
      throw usage_error("--target-fps adapts to measured frame times, which a --gaze-replay cannot repeat");
    fov::require_output("--gaze-log", o.gaze_log, {o.gaze_replay});
    if (!o.gaze_log.empty() && std::filesystem::exists(o.gaze_log))
      throw usage_error(fmt::format("--gaze-log {}: exists; choose a new file", o.gaze_log));
    if (!(o.target_fps >= 0 && o.target_fps <= 1000)) throw usage_error("--target-fps must lie in 0..1000");
    if (o.exit_after && o.frames == 0 && o.gaze_replay.empty()) throw usage_error("--exit needs --frames N (or a --gaze-replay)");
    if (!screenshot_at.empty()) {
      char* end = nullptr;
      o.screenshot_frame = std::strtol(screenshot_at[0].c_str(), &end, 10);
      if (*end || o.screenshot_frame < 0)
        throw usage_error(fmt::format("--screenshot-at: '{}' is not a frame number", screenshot_at[0]));
      o.screenshot_file = screenshot_at[1];
      fov::check_writable(o.screenshot_file);
    }
    return fov::run_viewer(o, settings);
  });
}
