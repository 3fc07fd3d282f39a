#!/usr/bin/env bash
# Foveal parity (issue 15, docs/speed-accuracy.md): the thesis's sets (--fovea darts) and
# sets whose fovea is a pixel grid (--fovea grid), s = 1.0, against full resolution at the
# same rays per sample (1, 4, 32) and the uniform baselines, every error against a converged
# 256-spp Sobol reference with its noise floor; the same three views as scripts/speed-accuracy.sh,
# centred gaze and one in the lower left. One fovbench run per layout and scene:
#   out/parity/{darts,grid,grid-1.10}/{builtin,helmet,env}
# References are cached per run under its references/; copying out/study/*/references there
# first (same views, same 256 spp) saves tracing them again. Then out/parity/tables.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=build/apps/fovbench
common=(--display fove --scales 1.0 --methods nn,shepard --k 5 --spp 1,4,32 --gazes "centre;320,1080"
        --frames 3 --reference-spp 256 --resume)
baselines=(--baselines full,uniform --uniform-fractions 0.5,0.25)
helmet=../shared/scenes/flight-helmet/FlightHelmet.gltf
env_map=/usr/share/blender/datafiles/studiolights/world/forest.exr
for fovea in darts grid; do
  "$bench" --scene builtin --sun-irradiance 0.8,0.77,0.7 --fovea $fovea "${common[@]}" "${baselines[@]}" -o out/parity/$fovea/builtin
done
for fovea in darts grid; do
  "$bench" --scene "env:$env_map" --fovea $fovea "${common[@]}" "${baselines[@]}" -o out/parity/$fovea/env
done
if [[ -f $helmet ]]; then
  for fovea in darts grid; do
    "$bench" --scene "$helmet" --eye 0.1,0.28,0.22 --look-at 0,0.3,0 --hfov 60 --fovea $fovea "${common[@]}" "${baselines[@]}" \
      -o out/parity/$fovea/helmet
  done
else
  echo "foveal-parity.sh: $helmet missing; no helmet sweep" >&2
fi
# The grid reaching 10.1° instead of 9.3° (--grid-spacing 1.1): beside full resolution only.
for scene in builtin env helmet; do
  case $scene in
    builtin) view=(--scene builtin --sun-irradiance 0.8,0.77,0.7) ;;
    env) view=(--scene "env:$env_map") ;;
    helmet) [[ -f $helmet ]] || continue; view=(--scene "$helmet" --eye 0.1,0.28,0.22 --look-at 0,0.3,0 --hfov 60) ;;
  esac
  "$bench" "${view[@]}" --fovea grid --grid-spacing 1.1 "${common[@]}" --baselines full -o out/parity/grid-1.10/$scene
done
# tables.md: per scene, gaze, spp and band, FLIP and PSNR of each layout's foveated frame and
# of full resolution at the same spp, the noise floors, the same-spp speedups, then each
# run's report.md (equal-error speedups).
python3 - out/parity <<'PY' > out/parity/tables.md
import csv, os, sys
root = sys.argv[1]
def rows(fovea, scene):
    path = os.path.join(root, fovea, scene, "results.csv")
    return list(csv.DictReader(open(path))) if os.path.exists(path) else []
def f3(r, c):
    v = r[c]
    return "inf" if v == "inf" else "-" if v == "" else f"{float(v):.3f}" if abs(float(v)) < 1 else f"{float(v):.2f}"
scenes = [s for s in ("builtin", "helmet", "env") if rows("grid", s) and rows("darts", s)]
print("# Foveal parity: FLIP (nn / Shepard k=5) and PSNR (Shepard) by band, against the 256-spp reference\n")
print("| scene | gaze | spp | full < 5° | darts < 5° | grid < 5° | full 5-10° | darts 5-10° | grid 5-10° | grid 1.1 5-10° | "
      "PSNR full < 5° | darts | grid | PSNR full 5-10° | darts | grid | grid 1.1 | Shepard > 30° darts | grid |")
print("|---|---|---:|" + "---:|" * 16)
for scene in scenes:
    darts, grid = rows("darts", scene), rows("grid", scene)
    for gaze in ("centre", "320_1080"):
        for spp in ("1", "4", "32"):
            def pick(source, kind, method):
                return next(r for r in source if r["gaze"] == gaze and r["spp"] == spp and r["kind"] == kind and r["method"] == method)
            f = pick(grid, "full", "full")
            dn, ds, gn, gs = pick(darts, "foveated", "nn"), pick(darts, "foveated", "shepard"), pick(grid, "foveated", "nn"), pick(grid, "foveated", "shepard")
            wide = rows("grid-1.10", scene)
            wn, ws = (pick(wide, "foveated", "nn"), pick(wide, "foveated", "shepard")) if wide else (None, None)
            cells = [f3(f, "flip_fovea"), f"{f3(dn, 'flip_fovea')} / {f3(ds, 'flip_fovea')}", f"{f3(gn, 'flip_fovea')} / {f3(gs, 'flip_fovea')}",
                     f3(f, "flip_5_10"), f"{f3(dn, 'flip_5_10')} / {f3(ds, 'flip_5_10')}", f"{f3(gn, 'flip_5_10')} / {f3(gs, 'flip_5_10')}",
                     f"{f3(wn, 'flip_5_10')} / {f3(ws, 'flip_5_10')}" if wn else "-",
                     f3(f, "psnr_fovea"), f3(ds, "psnr_fovea"), f3(gs, "psnr_fovea"), f3(f, "psnr_5_10"), f3(ds, "psnr_5_10"), f3(gs, "psnr_5_10"),
                     f3(ws, "psnr_5_10") if ws else "-",
                     f3(ds, "flip_periphery"), f3(gs, "flip_periphery")]
            print(f"| {scene} | {gaze.replace('_', ', ')} | {spp} | " + " | ".join(cells) + " |")
print("\nNoise floors (a second 256-spp reference against the first): " + "; ".join(
    f"{s} {r['gaze'].replace('_', ', ')}: FLIP < 5° {float(r['noise_floor_flip_fovea']):.4f}, PSNR < 5° {f3(r, 'noise_floor_psnr_fovea')}"
    for s in scenes for g in ("centre", "320_1080") for r in [next(x for x in rows("grid", s) if x["gaze"] == g)]) + "\n")
print("# Same-spp speedup (foveated frame against full resolution at its spp, median of 3 paired repetitions)\n")
print("| scene | gaze | spp | darts nn | grid nn | darts Shepard | grid Shepard |")
print("|---|---|---:|---:|---:|---:|---:|")
for scene in scenes:
    for gaze in ("centre", "320_1080"):
        for spp in ("1", "4", "32"):
            cells = []
            for method in ("nn", "shepard"):
                for fovea in ("darts", "grid"):
                    r = next(x for x in rows(fovea, scene) if x["gaze"] == gaze and x["spp"] == spp and x["kind"] == "foveated" and x["method"] == method)
                    cells.append(f"{float(r['speedup']):.2f} ({float(r['speedup_lo']):.2f}-{float(r['speedup_hi']):.2f})")
            print(f"| {scene} | {gaze.replace('_', ', ')} | {spp} | {cells[0]} | {cells[1]} | {cells[2]} | {cells[3]} |")
print()
import re
def speedups(path, pooling):
    text = open(path).read()
    start = "### Equal-error speedup over the best baseline (foveated_flip)" if pooling == "foveated_flip" else f"Pooled as `{pooling}`:"
    if start not in text: return "-"
    part = text[text.index(start) + len(start):]
    ends = [i for i in (part.find("Pooled as"), part.find("\n#")) if i >= 0]
    part = part[:min(ends)] if ends else part
    if "share no error level" in part: return "no overlap: every baseline errs less" if "Every baseline" in part else "no overlap"
    return ", ".join(v for v in re.findall(r"\| ([0-9.]+)x \|", part))
print("# Equal-error speedup over the best baseline, at five error levels across the fronts' overlap (highest error first)\n")
print("| scene | pooling | darts | grid |")
print("|---|---|---|---|")
for scene in scenes:
    for pooling in ("foveated_flip", "foveated_flip_worst_band", "flip", "flip_fovea"):
        print(f"| {scene} | {pooling} | " + " | ".join(speedups(os.path.join(root, f, scene, "report.md"), pooling) for f in ("darts", "grid")) + " |")
print()
for fovea in ("darts", "grid"):
    for scene in scenes:
        path = os.path.join(root, fovea, scene, "report.md")
        if os.path.exists(path):
            print(f"# report: {fovea} / {scene}\n")
            print(open(path).read())
PY
echo "foveal-parity.sh: tables in out/parity/tables.md"
