#!/usr/bin/env bash
# The speed/accuracy study of docs/speed-accuracy.md: two fovbench sweeps at the FOVE
# geometry (1280x1440) on the built-in scene and the flight helmet (when ../shared has it).
#   out/bench/          scale x method x k x rays per sample x gaze, timing and error
#   out/bench-temporal/ flicker along a camera path, with and without TAA
#   out/bench-temporal-pixel/ the same with foveated rays filtering textures over a pixel
# Interrupted? Run it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=(--scene builtin)
helmet=../shared/scenes/flight-helmet/FlightHelmet.gltf
if [[ -f $helmet ]]; then scenes+=(--scene "$helmet"); else echo "speed-accuracy.sh: $helmet missing; built-in scene only" >&2; fi
build/apps/fovbench "${scenes[@]}" --display fove --scales 1.0,1.25,1.5,1.75,2.0,2.5,3.0 --methods nn,shepard,rbf \
  --k 5,20 --spp 1,4,32 --gazes centre,corner --frames 3 --budget-psnr 25 -o out/bench --resume
build/apps/fovbench --scene builtin --display fove --scales 1.0,1.75 --methods nn,shepard,rbf --k 5 --spp 4 \
  --gazes centre --frames 1 --temporal-frames 8 -o out/bench-temporal --resume
build/apps/fovbench --scene builtin --display fove --scales 1.0,1.75 --methods nn,shepard,rbf --k 5 --spp 4 \
  --gazes centre --frames 1 --temporal-frames 8 --texture-footprint pixel -o out/bench-temporal-pixel --resume
# The tables of docs/speed-accuracy.md, from the two results.csv files.
python3 - out/bench/results.csv out/bench-temporal/results.csv out/bench-temporal-pixel/results.csv > out/bench/tables.md <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
temporal = list(csv.DictReader(open(sys.argv[2])))
temporal_pixel = list(csv.DictReader(open(sys.argv[3])))
f = lambda r, c: float(r[c])
name = lambda s: "built-in" if s == "builtin" else s.split("/")[-1]
scenes = list(dict.fromkeys(r["scene"] for r in rows))
def pick(**kw):
    return [r for r in rows if all(r[k] == v for k, v in kw.items())]

print("### Speedup and error against scale (centred gaze, 32 rays per sample, Shepard k = 5)\n")
print("| scene | scale | points traced | rays / reference rays | frame ms | reference ms | speedup | PSNR | PSNR < 5° | PSNR > 30° | foveated error |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for s in scenes:
    for r in pick(scene=s, gaze="centre", method="shepard", k="5", spp="32"):
        print(f"| {name(s)} | {r['scale']} | {int(r['points_traced']):,} | {f(r,'rays')/f(r,'reference_rays'):.3f} | {f(r,'frame_ms'):.0f} "
              f"| {f(r,'reference_ms'):.0f} | {f(r,'speedup'):.2f} | {f(r,'psnr'):.2f} | {f(r,'psnr_fovea'):.2f} | {f(r,'psnr_periphery'):.2f} | {f(r,'foveated_error'):.4f} |")

print("\n### Thesis Table 1 remade: centred against corner gaze (s = 1.0, 32 rays per sample, Shepard k = 5)\n")
print("| scene | gaze | points traced | frame ms | speedup |")
print("|---|---|---:|---:|---:|")
for s in scenes:
    for g in ("centre", "corner"):
        for r in pick(scene=s, gaze=g, method="shepard", k="5", spp="32", scale="1.00"):
            print(f"| {name(s)} | {g} | {int(r['points_traced']):,} | {f(r,'frame_ms'):.0f} | {f(r,'speedup'):.2f} |")

print("\n### Thesis Table 2 remade: reconstruction per frame (s = 1.0, centred gaze, median over scenes and spp)\n")
print("| method | k = 5 | k = 20 |")
print("|---|---:|---:|")
for m in ("nn", "shepard", "rbf"):
    cells = []
    for k in ("5", "20"):
        v = [f(r, "reconstruct_ms") for r in pick(method=m, scale="1.00", gaze="centre") if r["k"] == ("1" if m == "nn" else k)]
        cells.append(f"{statistics.median(v):.1f} ms" if v else "")
    print(f"| {m} | {cells[0]} | {cells[1]} |")

print("\n### The methods at the thesis's threshold scale s = 1.75 (centred gaze)\n")
print("| scene | spp | method | k | frame ms | speedup | PSNR | SSIM | PSNR < 5° | foveated error |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
for s in scenes:
    for spp in ("4", "32"):
        for r in pick(scene=s, gaze="centre", scale="1.75", spp=spp):
            print(f"| {name(s)} | {spp} | {r['method']} | {r['k']} | {f(r,'frame_ms'):.0f} | {f(r,'speedup'):.2f} | {f(r,'psnr'):.2f} "
                  f"| {f(r,'ssim'):.3f} | {f(r,'psnr_fovea'):.2f} | {f(r,'foveated_error'):.4f} |")

print("\n### Flicker along a camera path (built-in scene, 4 rays per sample, k = 5, 8 frames)\n")
print("| scale | method | flicker without TAA | with TAA | the reference's own |")
print("|---:|---|---:|---:|---:|")
for r in temporal:
    print(f"| {r['scale']} | {r['method']} | {f(r,'flicker'):.4f} | {f(r,'flicker_taa'):.4f} | {f(r,'flicker_reference'):.4f} |")

print("\n### Texture footprint of foveated rays: disc against pixel (the same sweeps)\n")
print("| scale | method | PSNR disc | PSNR pixel | PSNR > 30° disc | pixel | flicker disc | pixel | with TAA disc | pixel |")
print("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|")
for a, b in zip(temporal, temporal_pixel):
    assert (a["scale"], a["method"]) == (b["scale"], b["method"])
    print(f"| {a['scale']} | {a['method']} | {f(a,'psnr'):.2f} | {f(b,'psnr'):.2f} | {f(a,'psnr_periphery'):.2f} | {f(b,'psnr_periphery'):.2f} "
          f"| {f(a,'flicker'):.4f} | {f(b,'flicker'):.4f} | {f(a,'flicker_taa'):.4f} | {f(b,'flicker_taa'):.4f} |")
PY
echo "tables: out/bench/tables.md"
