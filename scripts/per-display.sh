#!/usr/bin/env bash
# One answer per display (issue 24, item 5; docs/speed-accuracy.md "One answer per display"):
# on each display given (default: fove quest3 vision-pro varjo-xr4 retinal), one scene
# (SCENE=builtin, helmet or env; default builtin; scripts/study-scene.sh), centred gaze, every
# scheme in single frames against full resolution at 1, 2 and 4 spp, judged in JOD against a
# 128-spp reference with its noise floor, 3 interleaved repetitions:
#   all/     sparse darts at s = 0.5 and 1.0 (Shepard k = 5; each point casting spp rays, or
#            spp falling to 1 with eccentricity), the full grid's falloff (spp at the gaze
#            falling to 1), a lower resolution (a uniform set of 1/4 of the pixels), full
#            resolution
#   grid-4/  the hybrid: a pixel grid wherever the model's spacing is at most 4 px, darts
#            beyond (s = 0.5), with full resolution again
# Both runs of a display share one pair of references. Sets are kept as k-NN cells in
# out/per-display/sets (their memory in out/per-display/sets.md). Then `fovbench summary` over
# every run of every scene measured so far, in out/per-display/summary/: summary.md (per scene,
# display and scheme: the equal-quality speedup at the cheapest full frame reaching 9.5 JOD,
# with its interval), summary.csv, speedup-vs-ppd and jod-vs-ppd.
# Interrupted? Run it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/study-scene.sh  # bench, fovgen, scene_name and study_scene
displays=("$@")
(( ${#displays[@]} )) || displays=(fove quest3 vision-pro varjo-xr4 retinal)
for display in "${displays[@]}"; do
  study_scene "$scene_name" "$display"
  top="out/per-display/$scene_name/$display"
  common=("${scene[@]}" --display "$display" --methods shepard --k 5 --gazes centre --frames 3 --reference-spp 128 --no-flip
          --neighbours cells --points-dir out/per-display/sets --spp 1,2,4 --point-ray-floors 1 --resume)
  mkdir -p "$top/references"
  for run in all grid-4; do
    mkdir -p "$top/$run"
    [[ -e "$top/$run/references" ]] || ln -s ../references "$top/$run/references"
    case $run in
      all) what=(--scales 0.5,1.0 --ray-floors 1 --baselines full,uniform --uniform-fractions 0.25) ;;
      grid-4) what=(--scales 0.5 --baselines full --fovea grid --grid-spacing 4) ;;
    esac
    "$bench" "${common[@]}" "${what[@]}" -o "$top/$run"
  done
done
# Memory per display: every set's points, file and neighbours in memory (fovgen info).
for set in out/per-display/sets/*.fovset; do "$fovgen" info --json "$set"; done > out/per-display/sets.json
python3 - out/per-display/sets.json > out/per-display/sets.md <<'PY'
import json, sys
dec, text, sets = json.JSONDecoder(), open(sys.argv[1]).read().strip(), []
while text:
    obj, end = dec.raw_decode(text)
    sets.append(obj)
    text = text[end:].strip()
sets.sort(key=lambda s: (s["pixels_per_degree"], s["file"]))
print("| set | ppd | pixels (M) | points | of them grid points | file (MB) | neighbours in memory (MB) |")
print("|---|---:|---:|---:|---:|---:|---:|")
for s in sets:
    name = s["file"].split("/")[-1]
    print(f"| `{name}` | {s['pixels_per_degree']:.1f} | {s['width'] * s['height'] / 1e6:.1f} | {s['points_total']:,} | "
          f"{s['grid_points']:,} | {s['file_bytes'] / 1e6:.1f} | {s['knn_memory_bytes'] / 1e6:.0f} |")
PY
cat out/per-display/sets.md
# One answer per scene, display and scheme, from these runs and the earlier studies' where
# present (scripts/hybrid-displays.sh, scripts/steady-state.sh): each cell the best any run gives.
inputs=(out/per-display/"$scene_name")
for d in out/per-display/builtin out/per-display/helmet out/per-display/env out/hybrid-displays out/steady-state; do
  [[ -d $d && $d != "${inputs[0]}" ]] && inputs+=("$d")
done
rm -rf out/per-display/summary
"$bench" summary "${inputs[@]}" -o out/per-display/summary
