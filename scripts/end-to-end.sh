#!/usr/bin/env bash
# End-to-end frames for docs/benchmarks.md: each scene at full resolution and foveated
# (Shepard, k = 5, s = 1.0 and 1.75), 32 rays per sample, centred gaze, one frame each,
# with speedup and PSNR/SSIM by eccentricity band. Prints a Markdown table, then a second
# one: foveated rays' texture footprint (disc or pixel) at s = 1.75 and 1, 4, 32 spp.
# Needs scripts/build.sh and precomputed/generate.sh bench first.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
fovrender="$root/build/apps/fovrender"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
scenes=("builtin")
helmet="$root/../shared/scenes/flight-helmet/FlightHelmet.gltf"
[[ -f "$helmet" ]] && scenes+=("$helmet")
echo "| scene | set | rays | trace + reconstruct | speedup | PSNR | SSIM | PSNR < 5° | 5-30° | > 30° | SSIM < 5° |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
footprints="$out/footprints.md"
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .gltf)
  "$fovrender" --reference --scene "$scene" --points "$root/precomputed/fove-s1.00.fovset" --spp 32 \
      -o "$out/ref.exr" --json > "$out/ref.json" 2>/dev/null
  for s in 1.00 1.75; do
    "$fovrender" --scene "$scene" --points "$root/precomputed/fove-s$s.fovset" --method shepard --k 5 --spp 32 \
        --compare "$out/ref.exr" --json > "$out/fov.json" 2>/dev/null
    python3 - "$out/ref.json" "$out/fov.json" "$name" "$s" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); f = json.load(open(sys.argv[2])); m = f["metrics"]
db = lambda v: "inf" if v is None else f"{v:.2f}"  # null: identical pixels
print(f"| {sys.argv[3]} | s = {sys.argv[4]} | {f['rays']/1e6:.2f} M of {r['rays']/1e6:.2f} M | "
      f"{f['trace_ms']:.0f} + {f['reconstruct_ms']:.0f} ms of {r['total_ms']:.0f} ms | {r['total_ms']/f['total_ms']:.2f}x | "
      f"{db(m['psnr'])} | {m['ssim']:.3f} | {db(m['psnr_fovea'])} | {db(m['psnr_mid'])} | {db(m['psnr_periphery'])} | {m['ssim_fovea']:.3f} |")
PY
  done
  for spp in 1 4 32; do
    for fp in disc pixel; do
      "$fovrender" --scene "$scene" --points "$root/precomputed/fove-s1.75.fovset" --method shepard --k 5 --spp $spp \
          --texture-footprint $fp --compare "$out/ref.exr" --json > "$out/fp.json" 2>/dev/null
      python3 - "$out/fp.json" "$name" >> "$footprints" <<'PY'
import json, sys
f = json.load(open(sys.argv[1])); m = f["metrics"]
db = lambda v: "inf" if v is None else f"{v:.2f}"
print(f"| {sys.argv[2]} | {f['spp']} | {f['texture_footprint']} | {f['trace_ms']:.0f} ms | {db(m['psnr'])} | {m['ssim']:.3f} "
      f"| {db(m['psnr_fovea'])} | {db(m['psnr_mid'])} | {db(m['psnr_periphery'])} |")
PY
    done
  done
done
echo
echo "| scene | spp | texture footprint | trace | PSNR | SSIM | PSNR < 5° | 5-30° | > 30° |"
echo "|---|---:|---|---:|---:|---:|---:|---:|---:|"
cat "$footprints"
