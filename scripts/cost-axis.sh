#!/usr/bin/env bash
# Cost as an axis of the study (issue 29; docs/speed-accuracy.md "Cost of a sample"): one scene
# (SCENE=cornell or helmet; scripts/study-scene.sh) on each display given (default: fove retinal),
# traced three ways: the direct integrator, and path tracing with 1 and with 3 bounces (INTEGRATORS
# to choose, e.g. INTEGRATORS="direct path3"). Each is its own fovbench run with its own
# references (REFERENCE_SPP, default 128, same integrator; its noise floor a second reference:
# path-traced references need 512 or more for a floor above 9.5 JOD, docs/metrics.md), centred gaze,
# 3 interleaved repetitions, every scheme against full resolution at 1, 2, 4 and 8 spp:
# sparse darts at s = 0.5 and 1.0 (Shepard k = 5; spp rays per point, or falling to 1 with
# eccentricity), the full grid's falloff (spp at the gaze falling to 1), a lower resolution
# (a uniform set of 1/4 of the pixels) and full resolution. Then `fovbench summary` over every
# run in out/cost-axis: the equal-quality speedup per scene, integrator and display at the
# cheapest full frame reaching 9.5 JOD, in out/cost-axis/summary.
# Interrupted? Run it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${SCENE:-cornell}
source scripts/study-scene.sh  # bench, fovgen, scene_name and study_scene
displays=("$@")
(( ${#displays[@]} )) || displays=(fove retinal)
read -r -a integrators <<< "${INTEGRATORS:-direct path1 path3}"
reference_spp=${REFERENCE_SPP:-128}
for display in "${displays[@]}"; do
  study_scene "$scene_name" "$display"
  for how in "${integrators[@]}"; do
    case $how in
      direct) traced=(--integrator direct) ;;
      path1) traced=(--integrator path --bounces 1) ;;
      path3) traced=(--integrator path --bounces 3) ;;
      *) echo "INTEGRATORS: '$how' is not direct, path1 or path3" >&2; exit 2 ;;
    esac
    top="out/cost-axis/$scene_name/$display/$how"
    mkdir -p "$top"
    "$bench" "${scene[@]}" "${traced[@]}" --display "$display" --methods shepard --k 5 --gazes centre --frames 3 \
      --reference-spp "$reference_spp" --no-flip --neighbours cells --points-dir out/cost-axis/sets --spp 1,2,4,8 \
      --point-ray-floors 1 --scales 0.5,1.0 --ray-floors 1 --baselines full,uniform --uniform-fractions 0.25 --resume -o "$top"
  done
done
inputs=()
for d in out/cost-axis/cornell out/cost-axis/helmet; do [[ -d $d ]] && inputs+=("$d"); done
rm -rf out/cost-axis/summary
"$bench" summary "${inputs[@]}" -o out/cost-axis/summary
