#!/usr/bin/env bash
# Two eyes with and without --reuse eyes (issue 28; docs/reuse.md "Measured: two eyes"): on a
# display (default fove) through the s = 1.0 set (Shepard k = 5) at SPP rays a point (default
# 4), both eyes rendered at a 63 mm IPD, each compared with its own converged reference
# (REFERENCE_SPP Sobol rays a pixel, default 64; floor: a second seed) by FovVideoVDP's JOD.
# Scenes (SCENES, default "builtin helmet env"; scripts/study-scene.sh): both gazes at the
# screens' centres; on builtin also a converged pair (GAZE_PAIR, default left 700,800 and right
# 660,800: 40 px of crossed disparity, the eyes converging at about 2 m on FOVE). Variants:
# every point of both eyes traced (none; none-seed2 at seed 2 with its own references: the
# JOD's spread between seeds), --reuse eyes at its defaults, with --reuse-fovea 0, with
# --reuse-fovea 0 --reuse-threshold 0, with --reuse-fovea 0 --reuse-view 2 or 5 (the view
# term), and with --reuse-fovea 0 --reuse-edges silhouettes --reuse-distance screen (VARIANTS
# picks some). One JSON a run and summary.md in out/stereo/DISPLAY.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/study-scene.sh  # bench, fovgen, render, study_scene, stereo_set
display=${1:-fove}
spp=${SPP:-4}
reference_spp=${REFERENCE_SPP:-64}
read -r -a pair <<< "${GAZE_PAIR:-700,800 660,800}"
out=out/stereo/$display
mkdir -p "$out"
stereo_set "$display"
read -r -a names <<< "${VARIANTS:-none none-seed2 eyes eyes-f0 eyes-f0-t0 eyes-f0-v2 eyes-f0-v5 eyes-f0-screen}"
declare -A variants=([none]="--reuse none" [none-seed2]="--reuse none --seed 2" [eyes]="--reuse eyes"
                     [eyes-f0]="--reuse eyes --reuse-fovea 0" [eyes-f0-t0]="--reuse eyes --reuse-fovea 0 --reuse-threshold 0"
                     [eyes-f0-v2]="--reuse eyes --reuse-fovea 0 --reuse-view 2"
                     [eyes-f0-v5]="--reuse eyes --reuse-fovea 0 --reuse-view 5"
                     [eyes-f0-screen]="--reuse eyes --reuse-fovea 0 --reuse-edges silhouettes --reuse-distance screen")
for name in ${SCENES:-builtin helmet env}; do
  if [[ $name == helmet && ! -f ../shared/scenes/flight-helmet/FlightHelmet.gltf ]]; then echo "(no helmet: ../shared absent)"; continue; fi
  study_scene "$name" "$display"
  gazes=(centre)
  [[ $name == builtin ]] && gazes+=(converged)
  for g in "${gazes[@]}"; do
    gaze=(--gaze centre)
    [[ $g == converged ]] && gaze=(--gaze "${pair[0]}" --gaze-right "${pair[1]}")
    for v in "${names[@]}"; do
      json=$out/$name-$g-$v.json
      read -r -a flags <<< "${variants[$v]}"
      [[ -s $json ]] || "$render" "${scene[@]}" --points "$set_file" --device cpp --spp "$spp" --stereo --ipd 63 "${gaze[@]}" \
        "${flags[@]}" --reference-spp "$reference_spp" --no-flip -o "$out/$name-$g-$v.png" --json > "$json"
    done
  done
done
python3 - "$out" "$spp" "$reference_spp" <<'PY' > "$out/summary.md"
import glob, json, os, sys
out, spp, reference_spp = sys.argv[1:]
print(f"{spp} rays a point, 63 mm IPD; JOD of each eye against its own converged reference of {reference_spp} rays a "
      f"pixel (floor: a second seed). Rays: primary (the right eye's probes included) and every ray (shadow rays too), "
      f"both eyes, against both eyes traced in full (none).\n")
print("| scene, gaze | variant | right eye: points kept (<5 / 5-10 / 10-15 / 15-30 / >30 deg) | primary rays, both eyes (ratio) | "
      "every ray, both eyes (ratio) | right eye's every ray vs left's | JOD left / right (floors) |")
print("|---|---|---|---|---|---|---|")
def total(e):
    return sum(e["rays_cast"].values())
for base in sorted(glob.glob(f"{out}/*-none.json")):
    stem = os.path.basename(base)[:-len("-none.json")]
    full = json.load(open(base))
    for v in ("none", "none-seed2", "eyes", "eyes-f0", "eyes-f0-t0", "eyes-f0-v2", "eyes-f0-v5", "eyes-f0-screen"):
        path = f"{out}/{stem}-{v}.json"
        if not os.path.exists(path):
            continue
        j = json.load(open(path))
        l, r = j["eyes"]["left"], j["eyes"]["right"]
        if "reuse" in r:
            b = r["reuse"]["by_eccentricity"]
            kept = f"{r['reuse']['reused_share']:.2f} (" + " / ".join(f"{x['reused'] / max(1, x['points']):.2f}" for x in b) + ")"
        else:
            kept = "-"
        p, pf = j["rays"], full["rays"]
        a, af = total(l) + total(r), total(full["eyes"]["left"]) + total(full["eyes"]["right"])
        jod = (f"{l['metrics']['jod']:.3f} / {r['metrics']['jod']:.3f} "
               f"({l['noise_floor']['jod']:.2f} / {r['noise_floor']['jod']:.2f})")
        print(f"| {stem} | {v} | {kept} | {p} ({p / pf:.2f}) | {a} ({a / af:.2f}) | {total(r) / total(l):.2f} | {jod} |")
PY
cat "$out/summary.md"
