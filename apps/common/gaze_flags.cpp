#include "gaze_flags.h"

#include <fmt/format.h>

#include "cli.h"
#include "fov/files.h"
#include "pupil_gaze.h"

namespace fov {

void add_gaze_flags(CLI::App& app, gaze_options& o) {
  app.add_option("--gaze-trace", o.trace, "Replay gaze from CSV (t_ms,x,y pixels or t_ms,x_norm,y_norm)");
  app.add_option("--gaze-trace-columns", o.trace_columns,
                 "--gaze-trace is another tool's export: pupil (Pupil Player gaze_positions.csv) or "
                 "TIME,X,Y[,CONFIDENCE][;time=ms|s|us][;coords=pixels|norm|norm-bottom-left]");
  app.add_option("--gaze-udp", o.udp,
                 "Gaze from UDP datagrams on 127.0.0.1:PORT: 'X Y' or 'v2 T C EYE X Y' (normalised, origin top-left)");
  app.add_option("--gaze-pupil", o.pupil, "Gaze from a Pupil Labs Core tracker: Pupil Remote at tcp://HOST:PORT (default port 50020)");
  app.add_option("--gaze-pupil-topic", o.pupil_topic, "With --gaze-pupil: the topic prefix to subscribe to (gaze. or surfaces.NAME)")->capture_default_str();
  app.add_option("--gaze-calibration", o.calibration,
                 "With --gaze-udp or --gaze-pupil: a JSON calibration (offset/scale, homography or a validation grid)");
  app.add_option("--gaze-min-confidence", o.conditioning.min_confidence, "Drop samples below this confidence (0..1)")->capture_default_str();
  app.add_option("--gaze-filter", o.filter, "Smooth the gaze with the 1-euro filter: MIN_CUTOFF_HZ,BETA (default off)")
      ->delimiter(',')
      ->expected(2);
  app.add_option("--saccade-deg-s", o.conditioning.saccade_deg_s,
                 "Saccade when the gaze moves faster than this (deg/s, I-VT; 0: off)")->capture_default_str();
  app.add_option("--gaze-hold-ms", o.conditioning.hold_ms,
                 "A silent tracker's last gaze is held this long, then the centre (safe mode)")->capture_default_str();
}

void require_valid(gaze_options& o) {
  if (o.sources() > 1) throw usage_error("choose one gaze source (--gaze-trace, --gaze-udp or --gaze-pupil)");
  if (!o.trace_columns.empty()) {
    if (o.trace.empty()) throw usage_error("--gaze-trace-columns maps the columns of a --gaze-trace file; give one");
    trace_columns c;
    if (const std::string why = parse_trace_columns(o.trace_columns, c); !why.empty())
      throw usage_error("--gaze-trace-columns " + why);
  }
  if (o.udp < 0 || o.udp > 65535) throw usage_error(fmt::format("--gaze-udp {}: not a port", o.udp));
  if (!o.pupil.empty()) {
    std::string host;
    uint16_t port = 0;
    if (const std::string why = parse_pupil_endpoint(o.pupil, host, port); !why.empty())
      throw usage_error(fmt::format("--gaze-pupil {}: {}", o.pupil, why));
  }
  if (o.pupil_topic.empty() || (o.pupil_topic.rfind("gaze", 0) != 0 && o.pupil_topic.rfind("surfaces.", 0) != 0) ||
      o.pupil_topic.size() > 64)
    throw usage_error(fmt::format("--gaze-pupil-topic '{}': a gaze topic prefix (gaze., gaze.3d., gaze.3d.01., ...) or a "
                                  "surface's (surfaces.NAME)", printable(o.pupil_topic, 64)));
  if (!o.calibration.empty() && o.udp == 0 && o.pupil.empty())
    throw usage_error("--gaze-calibration applies to --gaze-udp and --gaze-pupil");
  if (!o.filter.empty()) o.conditioning.min_cutoff_hz = o.filter[0], o.conditioning.beta = o.filter[1];
  if (const std::string why = gaze_conditioning_problem(o.conditioning); !why.empty()) throw usage_error(why);
}

std::unique_ptr<gaze_source> open_gaze(const gaze_options& o, int width, int height) {
  gaze_calibration calibration;
  if (!o.calibration.empty()) calibration = read_gaze_calibration(o.calibration);
  if (!o.trace.empty() && !o.trace_columns.empty()) {
    trace_columns c;
    parse_trace_columns(o.trace_columns, c);  // checked by require_valid
    return table_gaze(o.trace, c, width, height);
  }
  if (!o.trace.empty()) return trace_gaze(o.trace, width, height);
  if (o.udp) return udp_gaze(uint16_t(o.udp), width, height, calibration);
  if (!o.pupil.empty()) {
    pupil_params p;
    p.endpoint = o.pupil;
    p.topic = o.pupil_topic;
    return pupil_gaze(p, calibration, width, height);
  }
  return nullptr;
}

}  // namespace fov
