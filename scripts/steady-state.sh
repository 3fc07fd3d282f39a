#!/usr/bin/env bash
# Steady state with TAA (issue 24, item 4; docs/speed-accuracy.md "Steady state with TAA"):
# on each display given (default: fove), one scene (SCENE=builtin, helmet or env; default
# builtin) rendered as the study renders it (scripts/hybrid-displays.sh: the built-in scene's
# whites unclipped, the helmet's close-up, the forest env: map), centred gaze, Shepard k = 5,
# JOD against a 128-spp reference. Every row as a single frame and after TAA_FRAMES (default
# 32) frames of TAA with a still view, once with the thesis's mirrored patterns and once with
# new ray positions every frame (--pattern mirror, reseed): sparse sets at s = 0.5 and 1.0
# (darts, and the hybrid's grid fovea out to a 4-pixel spacing), each point casting 1 or 4
# rays and at 4 also falling to 1 with eccentricity; the full grid's falloff; a uniform set
# of 1/4 of the pixels; full resolution at 1, 2 and 4 spp, with TAA what a user runs.
#   out/steady-state/SCENE/DISPLAY/{darts,grid-4}/   results.csv, report.md, figures
# Smaller sweeps (a 70-ppd display): RUNS (default "darts grid-4"), PATTERNS (default "mirror
# reseed"), SPPS (default 1,2,4) and SCALES (default 0.5,1.0), e.g.
#   RUNS=darts PATTERNS=reseed SPPS=1,4 SCALES=0.5 TAA_FRAMES=16 scripts/steady-state.sh retinal
# The runs of a display share one pair of references (DISPLAY/references). Interrupted? Run
# it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/study-scene.sh  # bench, fovgen, scene_name and study_scene
taa_frames=${TAA_FRAMES:-32}
runs=(${RUNS:-darts grid-4})
patterns=(${PATTERNS:-mirror reseed})
for run in "${runs[@]}"; do
  [[ $run =~ ^(darts|grid-4)$ ]] || { echo "RUNS: '$run' is not darts or grid-4" >&2; exit 2; }
done
displays=("$@")
(( ${#displays[@]} )) || displays=(fove)
for display in "${displays[@]}"; do
  study_scene "$scene_name" "$display"
  top="out/steady-state/$scene_name/$display"
  common=("${scene[@]}" --display "$display" --methods shepard --k 5 --gazes centre --frames 3 --reference-spp 128 --no-flip
          --neighbours cells --points-dir out/hybrid-displays/sets --spp "${SPPS:-1,2,4}" --scales "${SCALES:-0.5,1.0}" --point-ray-floors 1
          --taa-frames "$taa_frames" --resume)
  mkdir -p "$top/references"
  for run in "${runs[@]}"; do
    mkdir -p "$top/$run"
    [[ -e "$top/$run/references" ]] || ln -s ../references "$top/$run/references"
    case $run in
      darts) what=(--baselines full,uniform --uniform-fractions 0.25 --ray-floors 1) ;;
      grid-4) what=(--baselines full --fovea grid --grid-spacing 4) ;;
    esac
    for pattern in "${patterns[@]}"; do
      "$bench" "${common[@]}" "${what[@]}" --pattern "$pattern" -o "$top/$run"
    done
  done
done
