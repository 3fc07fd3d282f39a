#!/usr/bin/env bash
# Where foveation pays, display by display (issue 24; docs/speed-accuracy.md "Across
# displays"): the built-in scene on FOVE (22 ppd), Quest 3 (25), Vision Pro (34), Varjo XR-4
# (51) and a 70-ppd retinal panel (docs/displays.md), each with the camera's horizontal field
# of view set to the display's, the full pixel grid at a foveated sampling rate (rays falling
# from each spp at a centred gaze to a floor of 1 or 2, --ray-floors) against full resolution
# at 1-16 spp, judged in JOD against a 128-spp converged reference with its noise floor.
# Sparse sets are left out (--no-sparse): their k-NN tables at 3840 x 3840 take 4.7 GB.
#   out/displays/DISPLAY/   results.csv, report.md (its verdict) and figures per display
# Interrupted? Run it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=${FOV_BENCH:-build/apps/fovbench}
fovgen=${FOV_GEN:-build/apps/fovgen}
for display in fove quest3 vision-pro varjo-xr4 retinal; do
  hfov=$("$fovgen" displays --display "$display" --json | python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)[0]["fov_deg"][0])')
  "$bench" --scene builtin --sun-irradiance 0.8,0.77,0.7 --display "$display" --hfov "$hfov" --no-sparse --scales 1.0 \
    --methods nn --ray-floors 1,2 --spp 1,2,4,8,16 --baselines full --gazes centre --frames 3 --reference-spp 128 \
    --no-flip --resume -o "out/displays/$display"
done
