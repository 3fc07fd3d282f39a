#!/usr/bin/env bash
# Detail the periphery detects but cannot resolve, restored as noise (issue 26's optional part;
# docs/adaptive.md "Detail as noise"): per scene (builtin, helmet close-up, env forest, as
# adaptive-study.sh renders them) and gaze (centre, 320,1080), the FOVE s = 1.0 set at SPP
# rays a point, Shepard k = 5, rendered with fovrender --detail-noise at each gain of GAINS
# (starting at 5 degrees, full 5 degrees further out) and at gain 1 from 0 and 10 degrees;
# each frame scored by fovbench compare (JOD, foveated FLIP by band) against one converged
# reference, beside the reference's noise floor (a second reference, another seed). Prints a
# markdown table. Usage: scripts/detail-noise-study.sh [OUT] [SPP] [REFERENCE_SPP]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/detail-noise}
spp=${2:-4}
ref_spp=${3:-64}
gains=${GAINS:-0 0.5 1 1.5 2}
bin=${BIN:-build/apps}  # the tools (BIN: a copy, to keep building while this runs)
gen=$bin/fovgen render=$bin/fovrender bench=$bin/fovbench
mkdir -p "$out"
set_file=$out/fove-s1.00.fovset
[[ -f $set_file ]] || "$gen" --display fove --scale 1.0 --k 8 --seed 1 -o "$set_file" > /dev/null
source scripts/adaptive-scenes.sh  # scene_flags, scene_missing, converged_pair
for scene in ${SCENES:-builtin helmet env}; do
  scene_missing $scene && continue
  flags=$(scene_flags $scene)
  d=$out/$scene
  converged_pair "$d" "$ref_spp" $flags
  for gaze in centre 320,1080; do
    g=$d/${gaze/,/-}
    mkdir -p "$g"
    "$bench" compare "$d/ref-b.exr" "$d/ref-a.exr" --display fove --gaze $gaze --json > "$g/floor.json"
    # gain:from:seed (the seed places the rays and draws the noise)
    variants=()
    for gain in $gains; do variants+=("$gain:5:1"); done
    variants+=("1:0:1" "1:10:1" "0:5:2" "1:5:2" "0:5:3" "1:5:3")
    for v in "${variants[@]}"; do
      IFS=: read -r gain from seed <<< "$v"
      name=g$gain-from$from; (( seed > 1 )) && name=$name-seed$seed
      [[ -f $g/$name.json ]] && continue  # measured already
      "$render" $flags --points "$set_file" --spp "$spp" --gaze $gaze --seed "$seed" --detail-noise "$gain" \
        --detail-noise-from "$from" -o "$g/$name.exr" -o "$g/$name.png" --json > "$g/$name-render.json"
      "$bench" compare "$g/$name.exr" "$d/ref-a.exr" --display fove --gaze $gaze --json > "$g/$name.json"
    done
  done
done
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
def load(g, name):
    return json.load(open(os.path.join(g, name + ".json"))), json.load(open(os.path.join(g, name + "-render.json")))
print("| scene | gaze | gain | from ° | JOD | vs gain 0 | FLIP <5° | 5-10° | 10-20° | 20-30° | >30° | foveated FLIP | reconstruct ms |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
paired = []
for scene in ("builtin", "helmet", "env"):
    for gaze in ("centre", "320-1080"):
        g = os.path.join(out, scene, gaze)
        if not os.path.isdir(g): continue
        floor = json.load(open(os.path.join(g, "floor.json")))
        base, _ = load(g, "g0-from5")
        names = [n[:-5] for n in os.listdir(g) if n.startswith("g") and n.endswith(".json") and "-render" not in n and "seed" not in n]
        names.sort(key=lambda n: (float(n[1:].split("-from")[0]), float(n.split("-from")[1])))
        where = f"| {scene} | {gaze.replace('-', ',')} |"
        for name in names:
            c, r = load(g, name)
            gain, frm = name[1:].split("-from")
            flips = " | ".join(f"{b['flip']:.4f}" for b in c["bands"])
            print(f"{where} {gain} | {frm} | {c['jod']:.3f} | {c['jod'] - base['jod']:+.3f} | {flips} | {c['foveated_flip']:.4f} | {r['reconstruct_ms']:.0f} |")
        flips = " | ".join(f"{b['flip']:.4f}" for b in floor["bands"])
        print(f"{where} noise floor | | {floor['jod']:.3f} | | {flips} | {floor['foveated_flip']:.4f} | |")
        deltas = []
        for suffix in ("", "-seed2", "-seed3"):
            try: deltas.append(load(g, "g1-from5" + suffix)[0]["jod"] - load(g, "g0-from5" + suffix)[0]["jod"])
            except FileNotFoundError: pass
        paired.append((scene, gaze, deltas))
print()
print("Gain 1 from 5° against gain 0, paired by seed (each seed its own rays and noise):")
print()
print("| scene | gaze | seeds | JOD change, mean | min | max |")
print("|---|---|---:|---:|---:|---:|")
for scene, gaze, d in paired:
    if d: print(f"| {scene} | {gaze.replace('-', ',')} | {len(d)} | {sum(d) / len(d):+.3f} | {min(d):+.3f} | {max(d):+.3f} |")
PY
