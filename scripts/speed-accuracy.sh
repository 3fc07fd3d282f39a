#!/usr/bin/env bash
# The speed/accuracy study of docs/speed-accuracy.md: one fovbench sweep per scene at the
# FOVE geometry (1280x1440), centred gaze and one in the lower left (on content in every
# view), foveated sets against the baselines a user would render
# instead (full resolution at each spp, uniform sets of 1/2 and 1/4 of the pixels), every
# error against a converged 256-spp Sobol reference with its noise floor.
#   out/study/builtin  the built-in scene, lit so that its whites do not clip
#   out/study/helmet   a close-up of the flight helmet (when ../shared has it)
#   out/study/env      an env: scene (a CC0 HDR map of blender-data)
# Interrupted? Run it again: --resume keeps every finished row. Then out/study/tables.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=build/apps/fovbench
common=(--display fove --scales 1.0,1.75 --methods nn,shepard --k 5 --spp 1,4,16 --gazes "centre;320,1080"
        --frames 3 --reference-spp 256 --baselines full,uniform --uniform-fractions 0.5,0.25 --resume)
"$bench" --scene builtin --sun-irradiance 0.8,0.77,0.7 "${common[@]}" -o out/study/builtin
helmet=../shared/scenes/flight-helmet/FlightHelmet.gltf
if [[ -f $helmet ]]; then
  "$bench" --scene "$helmet" --eye 0.1,0.28,0.22 --look-at 0,0.3,0 --hfov 60 "${common[@]}" -o out/study/helmet
else
  echo "speed-accuracy.sh: $helmet missing; no helmet sweep" >&2
fi
env_map=/usr/share/blender/datafiles/studiolights/world/forest.exr
"$bench" --scene "env:$env_map" "${common[@]}" -o out/study/env
# tables.md: each scene's report.md (equal-error speedups, fronts, noise floor, coverage),
# then per scene and band the foveated frame against the full-resolution frame with the
# same rays per sample (s = 1.0, centred gaze): the foveal parity of issue 15.
{
  for r in out/study/*/report.md; do sed 's/^# fovbench report/# '"$(basename "$(dirname "$r")")"'/' "$r"; echo; done
  python3 - out/study/*/results.csv <<'PY'
import csv, sys
bands = ["fovea", "5_10", "10_20", "20_30", "periphery"]
print("# Foveated (s = 1.00) against full resolution at the same spp, centred gaze: FLIP / PSNR by band\n")
for path in sys.argv[1:]:
    rows = [r for r in csv.DictReader(open(path)) if r["gaze"] == "centre"]
    if not rows: continue
    print(f"## {rows[0]['scene']}\n")
    print("| frame | spp | frame ms | " + " | ".join(f"FLIP {b}" for b in bands) + " | " + " | ".join(f"PSNR {b}" for b in bands) + " |")
    print("|---|---:|---:|" + "---:|" * (2 * len(bands)))
    for r in sorted(rows, key=lambda r: (int(r["spp"]), r["kind"], r["method"])):
        if not (r["kind"] == "full" or (r["kind"] == "foveated" and r["scale"] == "1.00")): continue
        name = "full resolution" if r["kind"] == "full" else f"foveated {r['method']} k={r['k']}"
        cells = [r[f"flip_{b}"] or "-" for b in bands] + [r[f"psnr_{b}"] or "-" for b in bands]
        fmt = lambda v: v if v in ("-", "inf") else f"{float(v):.3f}" if float(v) < 1 else f"{float(v):.2f}"
        print(f"| {name} | {r['spp']} | {float(r['frame_ms']):.0f} | " + " | ".join(fmt(c) for c in cells) + " |")
    fl = rows[0]
    print(f"\nnoise floor (a second 256-spp reference): FLIP {float(fl['noise_floor_flip']):.4f}, "
          f"FLIP < 5° {float(fl['noise_floor_flip_fovea']):.4f}, PSNR {fl['noise_floor_psnr']}, PSNR < 5° {fl['noise_floor_psnr_fovea']}\n")
PY
} > out/study/tables.md
echo "speed-accuracy.sh: tables in out/study/tables.md"
