#!/usr/bin/env bash
# Rays where the eye needs them on sparse sets (issue 24; docs/speed-accuracy.md "Rays per
# point and the hybrid at high pixels per degree"): on each display given (default: retinal
# varjo-xr4), the built-in scene as scripts/sparse-displays.sh renders it (centred gaze,
# Shepard k = 5, JOD against a 128-spp reference, full resolution at 1 and 4 spp beside),
# sets at s = 0.5 and 1.0 kept as k-NN cells, each point casting 1 or 4 rays, and at 4 rays
# also falling to 1 with eccentricity (--point-ray-floors 1); three fovea layouts, one
# results.csv each: darts (the thesis's), and the hybrid, a pixel grid wherever the model's
# spacing is at most 2 or 4 pixels (--fovea grid --grid-spacing 2|4), darts beyond.
#   out/hybrid-displays/DISPLAY/{darts,grid-2,grid-4}/   results.csv, report.md
# The three runs of a display share one pair of references (DISPLAY/references). Interrupted?
# Run it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=${FOV_BENCH:-build/apps/fovbench}
fovgen=${FOV_GEN:-build/apps/fovgen}
displays=("$@")
(( ${#displays[@]} )) || displays=(retinal varjo-xr4)
for display in "${displays[@]}"; do
  hfov=$("$fovgen" displays --display "$display" --json | python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)[0]["fov_deg"][0])')
  top="out/hybrid-displays/$display"
  mkdir -p "$top/references"
  for fovea in darts grid-2 grid-4; do
    layout=(--fovea darts)
    [[ $fovea == grid-* ]] && layout=(--fovea grid --grid-spacing "${fovea#grid-}")
    mkdir -p "$top/$fovea"
    [[ -e "$top/$fovea/references" ]] || ln -s ../references "$top/$fovea/references"
    "$bench" --scene builtin --sun-irradiance 0.8,0.77,0.7 --display "$display" --hfov "$hfov" --scales 0.5,1.0 \
      "${layout[@]}" --methods shepard --k 5 --spp 1,4 --point-ray-floors 1 --baselines full --gazes centre --frames 3 \
      --reference-spp 128 --no-flip --neighbours cells --points-dir out/hybrid-displays/sets --resume -o "$top/$fovea"
  done
done
