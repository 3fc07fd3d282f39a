#!/usr/bin/env bash
# The time two eyes take with and without --reuse eyes (issue 28; docs/reuse.md "Two eyes
# timed"): on a display (default fove) through the s = 1.0 set (Shepard k = 5, C++
# reconstruction) at SPP rays a point (default 4), both eyes at a 63 mm IPD and centred
# gazes, --taa-frames 4 (each eye's times are the last frame's, after three that warm the
# caches). REPEATS runs (default 5) of each variant in turn (none, then REUSE: default
# "--reuse eyes --reuse-fovea 0"), for each scene (SCENES, default "builtin helmet";
# scripts/study-scene.sh) and integrator (INTEGRATORS, default "direct path3": 3 bounces).
# The left eye does the same work in both variants: its times show the machine's noise.
# One JSON a run and timing.md in out/stereo-timing/DISPLAY.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/study-scene.sh  # bench, fovgen, render, study_scene, stereo_set
display=${1:-fove}
spp=${SPP:-4}
repeats=${REPEATS:-5}
reuse=${REUSE:---reuse eyes --reuse-fovea 0}
out=out/stereo-timing/$display
mkdir -p "$out"
stereo_set "$display"
declare -A traces=([direct]="--integrator direct" [path3]="--integrator path --bounces 3")
read -r -a reuse_flags <<< "$reuse"
for name in ${SCENES:-builtin helmet}; do
  if [[ $name == helmet && ! -f ../shared/scenes/flight-helmet/FlightHelmet.gltf ]]; then echo "(no helmet: ../shared absent)"; continue; fi
  study_scene "$name" "$display"
  for integrator in ${INTEGRATORS:-direct path3}; do
    read -r -a trace <<< "${traces[$integrator]}"
    for r in $(seq 1 "$repeats"); do
      for v in none reuse; do
        json=$out/$name-$integrator-$v-$r.json
        flags=(--reuse none)
        [[ $v == reuse ]] && flags=("${reuse_flags[@]}")
        [[ -s $json ]] || "$render" "${scene[@]}" --points "$set_file" --device cpp --spp "$spp" "${trace[@]}" --stereo --ipd 63 \
          --taa-frames 4 "${flags[@]}" -o "$out/$name-$integrator-$v.png" --json > "$json"
      done
    done
  done
done
python3 - "$out" "$repeats" "$reuse" <<'PY' > "$out/timing.md"
import json, os, statistics, sys
out, repeats, reuse = sys.argv[1], int(sys.argv[2]), sys.argv[3]
print(f"Both eyes, 63 mm IPD, centred gazes, the last of 4 TAA frames; {repeats} runs of each variant in turn; reuse: `{reuse}`. "
      "Trace ms: median (least-greatest) over the runs. Ratios: per run, reuse's over none's (the runs paired in order), "
      "median (least-greatest). The left eye does the same work in both: its ratio is the noise.\n")
print("| scene | integrator | left eye trace ms, none / reuse | right eye trace ms, none / reuse | left ratio | right ratio | "
      "both eyes' trace ratio | both eyes' frame ratio (trace, reconstruction, TAA) | right eye's every ray, reuse / none |")
print("|---|---|---|---|---:|---:|---:|---:|---:|")
def spread(v):
    return f"{statistics.median(v):.2f} ({min(v):.2f}-{max(v):.2f})"
def ms(v):
    return f"{statistics.median(v):.1f} ({min(v):.1f}-{max(v):.1f})"
for name in ("builtin", "helmet", "env", "cornell"):
    for integrator in ("direct", "path3"):
        runs = {v: [] for v in ("none", "reuse")}
        for v in runs:
            for r in range(1, repeats + 1):
                path = f"{out}/{name}-{integrator}-{v}-{r}.json"
                if os.path.exists(path):
                    runs[v].append(json.load(open(path)))
        if not runs["none"] or len(runs["none"]) != len(runs["reuse"]):
            continue
        eye = lambda j, e, k: j["eyes"][e][k]
        left = {v: [eye(j, "left", "trace_ms") for j in runs[v]] for v in runs}
        right = {v: [eye(j, "right", "trace_ms") for j in runs[v]] for v in runs}
        frame = {v: [sum(eye(j, e, k) for e in ("left", "right") for k in ("trace_ms", "reconstruct_ms", "taa_ms")) for j in runs[v]] for v in runs}
        ratio = lambda d: [b / a for a, b in zip(d["none"], d["reuse"])]
        both = {v: [a + b for a, b in zip(left[v], right[v])] for v in runs}
        cast = lambda j: sum(j["eyes"]["right"]["rays_cast"].values())
        print(f"| {name} | {integrator} | {ms(left['none'])} / {ms(left['reuse'])} | {ms(right['none'])} / {ms(right['reuse'])} | "
              f"{spread(ratio(left))} | {spread(ratio(right))} | {spread(ratio(both))} | {spread(ratio(frame))} | "
              f"{cast(runs['reuse'][0]) / cast(runs['none'][0]):.2f} |")
PY
cat "$out/timing.md"
