#!/usr/bin/env bash
# Rays where the eye needs them on sparse sets (issue 24; docs/speed-accuracy.md "Rays per
# point and the hybrid"): on each display given (default: retinal), one scene (SCENE=builtin,
# helmet or env; default builtin) rendered as the study renders it (the built-in scene's
# whites unclipped, the helmet's close-up, the forest env: map; the camera's field of view the
# display's, except the helmet's 60°), centred gaze, Shepard k = 5, JOD against a 128-spp
# reference, full resolution at 1 and 4 spp beside. Sets at s = 0.5 and 1.0 kept as k-NN
# cells, each point casting 1 or 4 rays, and at 4 rays also falling to 1 with eccentricity
# (--point-ray-floors 1); three fovea layouts, one results.csv each: darts (the thesis's),
# and the hybrid, a pixel grid wherever the model's spacing is at most 2 or 4 pixels
# (--fovea grid --grid-spacing 2|4), darts beyond. Then how dense a set must be: uniform sets
# of 1/4 and 1/16 of the pixels (a lower resolution, Shepard-upsampled) beside the s = 0.5
# darts, at 1 ray per point.
#   out/hybrid-displays/SCENE/DISPLAY/{darts,grid-2,grid-4,dense}/   results.csv, report.md
# RUNS="darts grid-4" measures only those (default: all four).
# The four runs of a display share one pair of references (DISPLAY/references). Interrupted?
# Run it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/study-scene.sh  # bench, fovgen, scene_name and study_scene
runs=(${RUNS:-darts grid-2 grid-4 dense})
for run in "${runs[@]}"; do
  [[ $run =~ ^(darts|grid-2|grid-4|dense)$ ]] || { echo "RUNS: '$run' is not darts, grid-2, grid-4 or dense" >&2; exit 2; }
done
displays=("$@")
(( ${#displays[@]} )) || displays=(retinal)
for display in "${displays[@]}"; do
  study_scene "$scene_name" "$display"
  top="out/hybrid-displays/$scene_name/$display"
  common=("${scene[@]}" --display "$display" --methods shepard --k 5 --gazes centre --frames 3 --reference-spp 128 --no-flip
          --neighbours cells --points-dir out/hybrid-displays/sets --resume)
  mkdir -p "$top/references"
  for run in "${runs[@]}"; do
    mkdir -p "$top/$run"
    [[ -e "$top/$run/references" ]] || ln -s ../references "$top/$run/references"
    case $run in
      darts) what=(--scales 0.5,1.0 --spp 1,4 --point-ray-floors 1 --baselines full) ;;
      grid-*) what=(--scales 0.5,1.0 --spp 1,4 --point-ray-floors 1 --baselines full --fovea grid --grid-spacing "${run#grid-}") ;;
      dense) what=(--scales 0.5 --spp 1 --baselines full,uniform --uniform-fractions 0.25,0.0625) ;;
    esac
    "$bench" "${common[@]}" "${what[@]}" -o "$top/$run"
  done
done
