#!/usr/bin/env bash
# The schemes side by side (issue 27, docs/schemes.md): one fovbench sweep per scheme
# (ACUITY:SAMPLER) on one display (default fove) and one scene (FOV_SCENE: builtin, the default,
# with its whites unclipped; helmet, the close-up of ../shared/scenes/flight-helmet the study
# uses; forest, the blender-data forest.exr env: scene), the camera's field of view the
# display's, centred gaze: the model's sets at
# s = 1.0, Shepard k = 5 at 1, 2 and 4 rays per point, against full resolution at 1, 2 and 4
# spp, 3 interleaved repetitions, JOD and FLIP against a 128-spp reference. Off the FOVE the
# sets keep k-NN cells (--neighbours cells, as scripts/sparse-displays.sh), on it their tables.
#   out/schemes/DISPLAY[-SCENE][-methods]/ACUITY-SAMPLER/   results.csv, report.md (SCENE unless builtin);
#   sets in out/schemes/sets
# FOV_TEMPORAL=N adds flicker and the video JOD along fovbench's temporal path of N frames
# (--temporal-frames; runs in out/schemes/DISPLAY[-SCENE]-temporal/), FOV_SPP the rays per
# point and pixel (default 1,2,4). FOV_METHODS (default shepard) and FOV_K (default 5) choose the
# reconstructions, e.g. FOV_METHODS=shepard,barycentric,natural FOV_K=12 (runs then in
# out/schemes/DISPLAY[-SCENE]-methods/).
# Usage: scripts/schemes-study.sh [DISPLAY [ACUITY:SAMPLER...]] (default: the thesis's csf:poisson,
# the MAR models with darts, and the papers' pairs linear-mar:polar and piecewise-mar:log-polar).
# Interrupted? Run it again (--resume).
set -euo pipefail
cd "$(dirname "$0")/.."
bench=${FOV_BENCH:-build/apps/fovbench}
fovgen=${FOV_GEN:-build/apps/fovgen}
display=${1:-fove}
shift || true
schemes=("$@")
(( ${#schemes[@]} )) || schemes=(csf:poisson linear-mar:poisson piecewise-mar:poisson linear-mar:polar piecewise-mar:log-polar)
scene=${FOV_SCENE:-builtin}
case $scene in
  builtin) scene_flags=(--scene builtin --sun-irradiance 0.8,0.77,0.7) where=$display ;;
  helmet) scene_flags=(--scene ../shared/scenes/flight-helmet/FlightHelmet.gltf --eye 0.1,0.28,0.22 --look-at 0,0.3,0)
    where=$display-helmet ;;
  forest) scene_flags=(--scene env:/usr/share/blender/datafiles/studiolights/world/forest.exr) where=$display-forest ;;
  *) echo "schemes-study.sh: FOV_SCENE must be builtin, helmet or forest (got '$scene')" >&2; exit 2 ;;
esac
temporal=()
[[ -z ${FOV_METHODS:-} ]] || where=$where-methods
if [[ -n ${FOV_TEMPORAL:-} ]]; then
  temporal=(--temporal-frames "$FOV_TEMPORAL")
  where=$where-temporal
fi
neighbours=()
[[ $display == fove ]] || neighbours=(--neighbours cells)
hfov=$("$fovgen" displays --display "$display" --json | python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)[0]["fov_deg"][0])')
first=""
for scheme in "${schemes[@]}"; do
  model=${scheme%%:*} sampler=${scheme#*:}
  run="out/schemes/$where/$model-$sampler"
  # The runs share one scene, display and reference: the first run's cached references serve
  # the others, the converged temporal paths included (hard links: each run keeps its own folder).
  if [[ -n $first && -d $first/references && ! -e $run/references ]]; then
    mkdir -p "$run" && cp -rl "$first/references" "$run/references"
  fi
  [[ -n $first ]] || first=$run
  "$bench" "${scene_flags[@]}" --display "$display" --hfov "$hfov" --acuity "$model" --sampler "$sampler" \
    --scales 1.0 --methods "${FOV_METHODS:-shepard}" --k "${FOV_K:-5}" --spp "${FOV_SPP:-1,2,4}" "${temporal[@]}" --baselines full --gazes centre --frames 3 --reference-spp 128 \
    "${neighbours[@]}" --points-dir out/schemes/sets --resume -o "$run"
done
