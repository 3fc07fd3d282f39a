#!/usr/bin/env bash
# Sparse sets where their tables did not fit (issue 24; docs/speed-accuracy.md "Sparse sets at
# high pixels per degree"): on each display given (default: varjo-xr4 retinal), the built-in
# scene as scripts/displays-study.sh renders it (its whites unclipped, the camera's field of
# view the display's, centred gaze), the thesis's sets at s = 0.5 (denser than the model) and
# s = 1.0 kept as k-NN cells, Shepard k = 5 at 1, 2 and 4 rays per point, against full
# resolution at 1, 2 and 4 spp, 3 interleaved repetitions, JOD against a 128-spp reference.
#   out/sparse-displays/DISPLAY/   results.csv, report.md (its verdict); sets in out/sparse-displays/sets
# Interrupted? Run it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=${FOV_BENCH:-build/apps/fovbench}
fovgen=${FOV_GEN:-build/apps/fovgen}
displays=("$@")
(( ${#displays[@]} )) || displays=(varjo-xr4 retinal)
for display in "${displays[@]}"; do
  hfov=$("$fovgen" displays --display "$display" --json | python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)[0]["fov_deg"][0])')
  "$bench" --scene builtin --sun-irradiance 0.8,0.77,0.7 --display "$display" --hfov "$hfov" --scales 0.5,1.0 \
    --methods shepard --k 5 --spp 1,2,4 --baselines full --gazes centre --frames 3 --reference-spp 128 --no-flip \
    --neighbours cells --points-dir out/sparse-displays/sets --resume -o "out/sparse-displays/$display"
done
