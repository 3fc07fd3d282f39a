#!/usr/bin/env bash
# What stratified rays inside the points' discs change (issue 15): the same small fovbench
# sweep with --disc-sampler random (the thesis's) and sobol, built-in scene (lit so its
# whites do not clip), FOVE s = 1.0, NN and Shepard k = 5, 1, 4 and 16 spp, centred gaze,
# against 256-spp Sobol references; prints FLIP and PSNR by band of both, and the
# full-resolution frames beside them. Writes out/disc-sampler/{random,sobol}/.
set -euo pipefail
cd "$(dirname "$0")/.."
for sampler in random sobol; do
  build/apps/fovbench --scene builtin --sun-irradiance 0.8,0.77,0.7 --display fove --scales 1.0 --methods nn,shepard \
    --k 5 --spp 1,4,16 --gazes centre --frames 1 --reference-spp 256 --disc-sampler $sampler --resume \
    -o out/disc-sampler/$sampler >/dev/null
done
python3 - out/disc-sampler/random/results.csv out/disc-sampler/sobol/results.csv <<'PY'
import csv, sys
bands = ["fovea", "5_10", "10_20", "20_30", "periphery"]
runs = {name: list(csv.DictReader(open(path))) for name, path in zip(("random", "sobol"), sys.argv[1:])}
print("| disc sampler | frame | spp | " + " | ".join(f"FLIP {b}" for b in bands) + " | PSNR < 5° | foveated FLIP |")
print("|---|---|---:|" + "---:|" * (len(bands) + 2))
for spp in ("1", "4", "16"):
    for name, rows in runs.items():
        for r in rows:
            if r["spp"] != spp or (r["kind"] == "full" and name == "sobol"): continue
            frame = "full resolution" if r["kind"] == "full" else f"{r['method']} k={r['k']}"
            label = "-" if r["kind"] == "full" else name
            print(f"| {label} | {frame} | {spp} | " + " | ".join(f"{float(r['flip_' + b]):.3f}" for b in bands) +
                  f" | {float(r['psnr_fovea']):.2f} | {float(r['foveated_flip']):.4f} |")
print(f"\nnoise floor: FLIP {float(runs['random'][0]['noise_floor_flip']):.4f}, FLIP < 5° {float(runs['random'][0]['noise_floor_flip_fovea']):.4f}")
PY
