#!/usr/bin/env bash
# Installs dependencies, builds, generates the default point set (FOVE, s = 1.0), renders
# the built-in scene foveated and at full resolution, and writes images and a
# timing/quality summary to out/demo/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
build=$("$root/scripts/build.sh" | tail -n 1)
fovgen="$build/apps/fovgen"
fovrender="$build/apps/fovrender"
out="$root/out/demo"
set_file="$root/precomputed/fove-s1.00.fovset"
mkdir -p "$out"

if ! "$fovgen" info "$set_file" >/dev/null 2>&1; then
  echo "generating $set_file ..."
  "$fovgen" --display fove --scale 1.0 --k 20 --seed 1 -o "$set_file"
fi
"$fovgen" info "$set_file" --gaze centre --json > "$out/set-centre.json"
"$fovgen" info "$set_file" --gaze corner --json > "$out/set-corner.json"
"$fovgen" plot "$set_file" -o "$out/points.png"
"$fovgen" plot "$set_file" --gaze centre -o "$out/points-gaze-centre.png"

echo "rendering the built-in scene at 1280x1440, 32 rays per pixel (reference) and per point (foveated) ..."
"$fovrender" --reference --points "$set_file" --spp 32 -o "$out/reference.exr" -o "$out/reference.png" --json > "$out/reference.json"
for m in nn shepard; do
  k=5; [[ $m == nn ]] && k=1
  "$fovrender" --points "$set_file" --gaze centre --method $m --k $k --spp 32 --speedup 7 \
      -o "$out/foveated-$m.png" --compare "$out/reference.exr" --json > "$out/foveated-$m.json"
done

python3 - "$out" > "$out/summary.txt" <<'PY'
import json, sys
out = sys.argv[1]
db = lambda v: "inf" if v is None else f"{v:.2f}"  # null: identical pixels
c = json.load(open(f"{out}/set-centre.json")); k = json.load(open(f"{out}/set-corner.json"))
ref = json.load(open(f"{out}/reference.json"))
print(f"point set        {c['file']}")
print(f"screen           {c['width']}x{c['height']}, v = {c['viewing_distance']}, s = {c['scale']}, k = {c['k']}")
print(f"points           {c['points_total']} (free area left {c['free_fraction']:.2e}, spacing violations {c['spacing_violations']})")
print(f"traced, centred  {c['points_traced']} ({100*c['traced_fraction']:.2f} %)   thesis Table 1: 420,248 (72.86 %)")
print(f"traced, corner   {k['points_traced']} ({100*k['traced_fraction']:.2f} %)   thesis Table 1: 153,857 (26.68 %)")
print()
print(f"built-in scene, centred gaze, 32 rays per sample, against the full-resolution frame with the same rays per pixel;")
print(f"speedup: median of 7 paired repetitions (a full-resolution frame timed right before each foveated one) and its 95 % bootstrap interval")
print(f"{'':12} {'rays':>10} {'speedup (95 % interval)':>24} {'JOD':>5} {'JOD nonfov':>10} {'PSNR dB':>8} {'SSIM':>6} {'PSNR <5deg':>10} {'5-30deg':>8} {'>30deg':>7} {'FLIP':>6} {'fov.FLIP':>8}")
print(f"{'reference':12} {ref['rays']:>10} {'1.00':>24}")
for m in ("nn", "shepard"):
    f = json.load(open(f"{out}/foveated-{m}.json")); mt = f["metrics"]
    speed = f"{f['speedup']:.2f}x ({f['speedup_interval'][0]:.2f}-{f['speedup_interval'][1]:.2f})"
    print(f"{m + ' k=' + str(f['k']):12} {f['rays']:>10} {speed:>24} {mt['jod']:>5.2f} {mt['jod_nonfoveated']:>10.2f} "
          f"{db(mt['psnr']):>8} {mt['ssim']:>6.3f} {db(mt['psnr_fovea']):>10} {db(mt['psnr_mid']):>8} {db(mt['psnr_periphery']):>7} "
          f"{mt['flip']:>6.3f} {mt['foveated_flip']:>8.3f}")
print("JOD: FovVideoVDP, 10 = no visible difference from the full-resolution frame; 1 JOD apart = 75 % of observers prefer the better")
print()
print(f"images           {out}/reference.png, foveated-nn.png, foveated-shepard.png, points*.png")
print("reconstruction ran on:", json.load(open(f"{out}/foveated-shepard.json"))["device"])
print("also: fovrender --method rbf (weights solved once, then OpenCL), --taa-frames N; fovbench for the full speed/accuracy sweep (docs/speed-accuracy.md)")
PY
cat "$out/summary.txt"
