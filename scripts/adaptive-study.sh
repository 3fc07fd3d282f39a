#!/usr/bin/env bash
# Nested sets and per-frame refinement against fixed sets (docs/adaptive.md): file size and
# load time of a FOVE nested set beside single-scale sets, then, per scene at a centred gaze,
# every level of the nested set rendered as a fixed set (--level) and adaptive frames at
# several thresholds, each against one converged reference, with the reference's noise floor
# (a second reference, another seed). Prints markdown tables (scripts/adaptive_tables.py: the
# frames, then each adaptive frame against the fixed sets at equal rays and equal quality).
# Usage: scripts/adaptive-study.sh [OUT] [SPP] [REFERENCE_SPP]   (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/adaptive}
spp=${2:-4}
ref_spp=${3:-64}
gen=build/apps/fovgen render=build/apps/fovrender bench=build/apps/fovbench
mkdir -p "$out"
levels=0.7,1.0,1.5,2.25,3.0
nested=$out/fove-n0.70-1.00-1.50-2.25-3.00.fovset
[[ -f $nested ]] || "$gen" --display fove --levels $levels --k 8 --seed 1 -o "$nested" --json > "$out/gen-nested.json"
for s in 0.70 1.00 3.00; do
  [[ -f $out/fove-s$s.fovset ]] || "$gen" --display fove --scale $s --k 8 --seed 1 -o "$out/fove-s$s.fovset" --json > "$out/gen-s$s.json"
done

echo "### Files (FOVE, k = 8)"
echo
echo "| set | points | file MB | generation s | load ms | levels setup ms |"
echo "|---|---:|---:|---:|---:|---:|"
for f in "$nested" "$out"/fove-s0.70.fovset "$out"/fove-s1.00.fovset "$out"/fove-s3.00.fovset; do
  extra=(); [[ $f == "$nested" ]] && extra=(--adaptive)
  "$render" --points "$f" --spp 1 --no-warmup "${extra[@]}" -o "$out/load.png" --json > "$out/load.json"
  "$gen" info "$f" --json > "$out/info.json"
  python3 - "$f" "$out/load.json" "$out/info.json" <<'PY'
import json, os, sys
f, j, i = sys.argv[1], json.load(open(sys.argv[2])), json.load(open(sys.argv[3]))
name = os.path.basename(f)
print(f"| {name} | {i['points_total']:,} | {os.path.getsize(f) / 1e6:.1f} | {i['generation_seconds']:.0f} | "
      f"{j['set_load_ms']:.0f} | {j.get('levels_setup_ms', 0):.0f} |")
PY
done
echo

scene_flags() {
  case $1 in
    builtin) echo "--scene builtin" ;;
    helmet) echo "--scene ../shared/scenes/flight-helmet/FlightHelmet.gltf --eye 0.1,0.28,0.22 --look-at 0,0.3,0 --hfov 60" ;;
    env) echo "--scene env:/usr/share/blender/datafiles/studiolights/world/forest.exr" ;;
  esac
}
for scene in ${SCENES:-builtin helmet env}; do
  flags=$(scene_flags $scene)
  if [[ $scene == helmet && ! -f ../shared/scenes/flight-helmet/FlightHelmet.gltf ]]; then echo "(no helmet: ../shared absent)"; continue; fi
  d=$out/$scene
  mkdir -p "$d"
  # Two converged references, different seeds: the first is the truth, the second its noise floor.
  [[ -f $d/ref-a.exr ]] || "$render" $flags --display fove --reference --spp "$ref_spp" --seed 1001 -o "$d/ref-a.exr" > /dev/null
  [[ -f $d/ref-b.exr ]] || "$render" $flags --display fove --reference --spp "$ref_spp" --seed 1002 -o "$d/ref-b.exr" > /dev/null
  for gaze in centre 320,1080; do
    g=$d/${gaze/,/-}
    mkdir -p "$g"
    "$bench" compare "$d/ref-b.exr" "$d/ref-a.exr" --display fove --gaze $gaze --json > "$g/floor.json"
    "$render" $flags --display fove --reference --spp "$spp" --gaze $gaze -o "$g/full.png" --compare "$d/ref-a.exr" --json > "$g/full.json"
    # Each frame timed against full resolution at the same spp, pair by pair (--speedup), and
    # its flicker along a slow turn (--flicker).
    timing=(--speedup "${PAIRS:-5}" --flicker 6 --gaze $gaze)
    for l in 0 1 2 3 4; do
      "$render" $flags --points "$nested" --level $l --spp "$spp" "${timing[@]}" -o "$g/level$l.png" \
        --compare "$d/ref-a.exr" --json > "$g/level$l.json"
    done
    for t in 1 0.5 0.25; do
      "$render" $flags --points "$nested" --adaptive --adaptive-threshold $t --spp "$spp" "${timing[@]}" -o "$g/adaptive$t.png" \
        --debug-view refinement --compare "$d/ref-a.exr" --json > "$g/adaptive$t.json"
    done
  done
done
# The tables of every scene and gaze (docs/adaptive.md), from the JSON files above.
python3 scripts/adaptive_tables.py "$out" "$spp" "$ref_spp" ${SCENES:-builtin helmet env}
