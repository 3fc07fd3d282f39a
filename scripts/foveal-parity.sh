#!/usr/bin/env bash
# Foveal parity (issue 15, docs/speed-accuracy.md): the thesis's sets (--fovea darts) and
# sets whose fovea is a pixel grid (--fovea grid), s = 1.0, against full resolution at the
# same rays per sample (1, 4, 32) and the uniform baselines, every error against a converged
# 256-spp Sobol reference with its noise floor; the same three views as scripts/speed-accuracy.sh,
# centred gaze and one in the lower left. One fovbench run per layout and scene:
#   out/parity/{darts,grid}/{builtin,helmet,env}
# References are cached per run under its references/; copying out/study/*/references there
# first (same views, same 256 spp) saves tracing them again. Then out/parity/tables.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=build/apps/fovbench
common=(--display fove --scales 1.0 --methods nn,shepard --k 5 --spp 1,4,32 --gazes "centre;320,1080"
        --frames 3 --reference-spp 256 --baselines full,uniform --uniform-fractions 0.5,0.25 --resume)
helmet=../shared/scenes/flight-helmet/FlightHelmet.gltf
env_map=/usr/share/blender/datafiles/studiolights/world/forest.exr
for fovea in darts grid; do
  "$bench" --scene builtin --sun-irradiance 0.8,0.77,0.7 --fovea $fovea "${common[@]}" -o out/parity/$fovea/builtin
done
for fovea in darts grid; do
  "$bench" --scene "env:$env_map" --fovea $fovea "${common[@]}" -o out/parity/$fovea/env
done
if [[ -f $helmet ]]; then
  for fovea in darts grid; do
    "$bench" --scene "$helmet" --eye 0.1,0.28,0.22 --look-at 0,0.3,0 --hfov 60 --fovea $fovea "${common[@]}" \
      -o out/parity/$fovea/helmet
  done
else
  echo "foveal-parity.sh: $helmet missing; no helmet sweep" >&2
fi
# tables.md: per scene, gaze and band, FLIP and PSNR of each layout's foveated frame and of
# full resolution at the same spp, with the noise floor; then each run's report.md headline.
python3 - out/parity <<'PY' > out/parity/tables.md
import csv, os, sys
root = sys.argv[1]
bands = [("fovea", "< 5°"), ("5_10", "5-10°"), ("10_20", "10-20°"), ("periphery", "> 30°")]
def rows(fovea, scene):
    path = os.path.join(root, fovea, scene, "results.csv")
    return list(csv.DictReader(open(path))) if os.path.exists(path) else []
def f3(v):
    if v in ("", None): return "-"
    if v == "inf": return "inf"
    x = float(v)
    return f"{x:.3f}" if abs(x) < 1 else f"{x:.2f}"
for scene in ("builtin", "helmet", "env"):
    darts, grid = rows("darts", scene), rows("grid", scene)
    if not grid: continue
    print(f"## {scene}\n")
    for gaze in ("centre", "320_1080"):
        print(f"### gaze {gaze}\n")
        print("| frame | spp | rays | frame ms | speedup | " + " | ".join(f"FLIP {b}" for _, b in bands) + " | " +
              " | ".join(f"PSNR {b}" for _, b in bands) + " |")
        print("|---|---:|---:|---:|---:|" + "---:|" * (2 * len(bands)))
        for spp in ("1", "4", "32"):
            for label, source, kind in (("full resolution", grid, "full"), ("darts", darts, "foveated"), ("grid", grid, "foveated")):
                for r in source:
                    if r["gaze"] != gaze or r["spp"] != spp or r["kind"] != kind: continue
                    name = label if kind == "full" else f"{label} {r['method']} k={r['k']}"
                    sp = f"{float(r['speedup']):.2f} ({float(r['speedup_lo']):.2f}-{float(r['speedup_hi']):.2f})" if kind != "full" else "-"
                    print(f"| {name} | {spp} | {int(r['rays'])/1e6:.2f} M | {float(r['frame_ms']):.0f} | {sp} | " +
                          " | ".join(f3(r['flip_' + b]) for b, _ in bands) + " | " + " | ".join(f3(r['psnr_' + b]) for b, _ in bands) + " |")
        fl = next(r for r in grid if r["gaze"] == gaze)
        print(f"\nnoise floor (a second 256-spp reference): FLIP {float(fl['noise_floor_flip']):.4f}, FLIP < 5° "
              f"{float(fl['noise_floor_flip_fovea']):.4f}, PSNR {f3(fl['noise_floor_psnr'])}, PSNR < 5° {f3(fl['noise_floor_psnr_fovea'])}\n")
for fovea in ("darts", "grid"):
    for scene in ("builtin", "helmet", "env"):
        path = os.path.join(root, fovea, scene, "report.md")
        if os.path.exists(path):
            print(f"# report: {fovea} / {scene}\n")
            print(open(path).read())
PY
echo "foveal-parity.sh: tables in out/parity/tables.md"
