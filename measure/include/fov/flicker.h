// The flicker experiment: how much a foveated frame changes from one frame to the next
// along a slow camera turn with a drifting gaze, raw and with TAA, beside what the
// full-resolution reference itself changes; and, against converged frames along the same
// path, how visible the moving sequences' differences are (FovVideoVDP's video JOD, the
// gaze following the drift frame by frame).
#pragma once

#include <cstdint>
#include <vector>

#include "fov/fvvdp.h"
#include "fov/renderer.h"

namespace fov {

struct flicker_params {
  uint32_t frames = 8;               // 2 or more
  float yaw_deg_per_frame = 0.15f;   // the camera turns right about its up axis
  float shift_per_frame = 0;         // and moves right (world units along its right) each frame
  double gaze_px_per_frame = 3;      // the gaze drifts right (clamped to the screen)
  double fps = 60;                   // the display's frame rate, for the video JOD (8..1000)
  display_photometry photometry;     // the display's light, for the video JOD
  bool full_resolution = true;       // also trace the full-resolution frame (reference, jod_full)
  // The TAA sequence blends the raw frames' samples (false: the flicker experiment, both
  // sequences from the same rays), or traces its own with the TAA pattern, which moves the
  // seed every frame as fovview's and fovrender's TAA do (true: what a viewer of TAA sees,
  // still views included).
  bool taa_own_rays = false;
};

// Frame n of the path: the camera `still` moved right by n x shift and turned right by n x
// yaw, the gaze moved from `start`.
camera path_camera(const camera& still, const flicker_params& f, uint32_t n);
gaze_point path_gaze(gaze_point start, const display_geometry& d, const flicker_params& f, uint32_t n);

// Converged frames along the path (colour only; the gaze does not change them): `spp` Sobol
// rays per pixel with the seed `seed` (compare_converged's are converged_seeds(p.seed)), at
// the size of the set in use; a path whose camera does not turn is traced once and its frame
// repeated. The renderer's camera is restored afterwards.
std::vector<frame> converged_path(renderer& r, const render_params& p, uint32_t spp, uint64_t seed,
                                  const flicker_params& f = {});

// Mean frame-to-frame change of display luminance (mean_luminance_change), over frames - 1 pairs.
struct flicker_report {
  double raw = 0;        // the reconstructed frames
  double taa = 0;        // the same samples blended by TAA (p.temporal)
  double reference = 0;  // full-resolution frames at p.spp rays per pixel (f.full_resolution)
  // Video JOD of the sequences against the converged frames, when given (jod_full only
  // with f.full_resolution; otherwise it stays at 10 for 0 frames).
  bool has_jod = false;
  fvvdp_result jod_raw, jod_taa, jod_full;
};

// Each frame is traced once with the pattern fixed (p.seed: the rays move only with the
// camera) and reconstructed twice, without and with TAA, from the same samples; the
// reference is traced with the same seed. The renderer's camera and TAA history are
// restored afterwards. With `converged` (converged_path's frames, one per frame of the
// path), each sequence's video JOD against it too. Throws std::invalid_argument for a
// `converged` of another length or frame size.
flicker_report measure_flicker(renderer& r, gaze_point start, const render_params& p, const flicker_params& f = {},
                               const std::vector<frame>& converged = {});

// Temporal reuse along the path (issue 28; fov/reuse.h): the path's frames traced twice with
// p's ray pattern (p.taa as given), every point traced each frame and with p.reuse (its
// history dropped first), each reconstructed. Per frame, the rays each cast (with reuse: the
// traced points' rays and the probes) and what reuse kept; for each sequence its flicker (mean
// frame-to-frame luminance change) and, with `converged` (converged_path's frames), its video
// JOD against them. The renderer's camera and histories are restored or dropped afterwards.
struct reuse_path_report {
  std::vector<uint64_t> rays_full, rays_reuse;  // primary rays (with reuse: the probes too)
  // Trace time (probes, candidates and traced points; reconstruction is the same work for
  // both), side by side: `timing_repeats` more passes along the path, each frame traced in full
  // and then with reuse (its history carried along that pass), frame 0 left out. Per pair the
  // two times in ms.
  std::vector<double> trace_ms_full, trace_ms_reuse;
  // With time_full_resolution: in the same passes, beside each pair, the full pixel grid at
  // p.spp traced from the same pose (what a user would do without foveation), in ms.
  std::vector<double> trace_ms_full_resolution;
  std::vector<uint64_t> cast_full, cast_reuse;  // every ray: primary, shadow and bounce
  std::vector<reuse_report> reuse;
  double flicker_full = 0, flicker_reuse = 0;
  bool has_jod = false;
  fvvdp_result jod_full, jod_reuse;
  // Per timing pair, the reusing trace's time over the full trace's.
  std::vector<double> trace_ratios() const;
};
// The mean of a per-frame figure of the path over the frames after the first (frame 0 has
// nothing to keep); 0 for fewer than two frames.
template <class T>
double mean_after_first(const std::vector<T>& per_frame) {
  double sum = 0;
  for (size_t i = 1; i < per_frame.size(); ++i) sum += double(per_frame[i]);
  return per_frame.size() > 1 ? sum / double(per_frame.size() - 1) : 0.0;
}
// The traces of each timing pass run in turn, each pass starting one later than the last.
reuse_path_report measure_reuse(renderer& r, gaze_point start, const render_params& p, const flicker_params& f,
                                const std::vector<frame>& converged = {}, uint32_t timing_repeats = 3,
                                bool time_full_resolution = false);

// Video JOD of one converged path against another (converged_path with the two seeds of
// converged_seeds): the noise floor of every video JOD measured against the first.
fvvdp_result converged_path_floor(const std::vector<frame>& second, const std::vector<frame>& first, gaze_point start,
                                  const display_geometry& d, const flicker_params& f = {});

}  // namespace fov
