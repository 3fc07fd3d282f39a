#!/usr/bin/env bash
# The foveated FLIP on the thesis's scale sweep (docs/metrics.md). The thesis's observers
# compared a foveated frame with the full-resolution frame of the same rays per sample; so
# does this: Shepard k = 5 frames at s = 1.0 ... 3.0 against the full-resolution frame at
# 4 spp (the thesis protocol's), centred gaze, on the staircase's env: scene (city.exr)
# and the built-in scene (lit so its whites do not clip). Beside them, the same
# full-resolution frame with another seed: a difference of ray noise alone, which no
# observer would call foveation. Writes out/scale-visibility/table.md.
set -euo pipefail
cd "$(dirname "$0")/.."
for s in 1.00 1.50 2.00 2.50 3.00; do  # the sets fovbench and generate.sh make, when missing
  [[ -f precomputed/fove-s$s.fovset ]] || build/apps/fovgen --display fove --scale $s --k 20 --seed 1 -o precomputed/fove-s$s.fovset
done
out=out/scale-visibility
mkdir -p "$out"
render=build/apps/fovrender
for scene in env:/usr/share/blender/datafiles/studiolights/world/city.exr builtin; do
  name=$([[ $scene == builtin ]] && echo builtin || echo city)
  light=(); [[ $scene == builtin ]] && light=(--sun-irradiance 0.8,0.77,0.7)
  "$render" --scene "$scene" "${light[@]}" --reference --points precomputed/fove-s1.00.fovset --spp 4 -o "$out/$name-full.exr"
  "$render" --scene "$scene" "${light[@]}" --reference --points precomputed/fove-s1.00.fovset --spp 4 --seed 2 \
    -o "$out/$name-full-seed2.exr" --compare "$out/$name-full.exr" --json > "$out/$name-seed2.json"
  for s in 1.00 1.50 2.00 2.50 3.00; do
    "$render" --scene "$scene" "${light[@]}" --points "precomputed/fove-s$s.fovset" --spp 4 --method shepard --k 5 \
      -o "$out/$name-s$s.png" --compare "$out/$name-full.exr" --json > "$out/$name-s$s.json"
  done
done
python3 - "$out" > "$out/table.md" <<'PY'
import json, sys
out = sys.argv[1]
print("| scene | frame against full resolution, 4 spp | FLIP | FLIP < 5° | foveated FLIP | its worst band | its p99 | PSNR |")
print("|---|---|---:|---:|---:|---:|---:|---:|")
for name in ("city", "builtin"):
    rows = [("full resolution, another seed", f"{out}/{name}-seed2.json")] + \
           [(f"foveated s = {s}", f"{out}/{name}-s{s}.json") for s in ("1.00", "1.50", "2.00", "2.50", "3.00")]
    for label, path in rows:
        m = json.load(open(path))["metrics"]
        psnr = "inf" if m["psnr"] is None else f"{m['psnr']:.2f}"
        print(f"| {name} | {label} | {m['flip']:.4f} | {m['flip_fovea']:.4f} | {m['foveated_flip']:.4f} | "
              f"{m['foveated_flip_worst_band']:.4f} | {m['foveated_flip_p99']:.4f} | {psnr} |")
PY
cat "$out/table.md"
