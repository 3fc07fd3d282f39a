#!/usr/bin/env bash
# fovrender and fovbench time reconstruction the same way (docs/benchmarks.md): both drive
# fov::renderer, which reconstructs into its reused frame after an untimed warm-up. For
# each method (k = 5, FOVE s = 1.0, 4 spp, centred gaze, OpenCL on the default device),
# REPS rounds that run fovrender once and fovbench once (--frames 1) in turn, so the two
# see the same machine load (fovbench with a cheap 8-spp reference and no FLIP: only its
# timing is read); prints each tool's median, min and max reconstruct_ms.
# Usage: scripts/reconstruct-timing.sh [REPS]   (default 5; needs scripts/build.sh and
# precomputed/generate.sh default)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${FOV_BUILD:-$root/build}  # another build tree (e.g. of an older commit) to compare
reps=${1:-5}
set_file="$root/precomputed/fove-s1.00.fovset"
[[ -f "$set_file" ]] || { echo "reconstruct-timing.sh: $set_file missing (precomputed/generate.sh default)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir -p "$out/sets"
ln -s "$set_file" "$out/sets/fove-s1.00.fovset"
for rep in $(seq 1 "$reps"); do
  for method in nn shepard rbf; do
    k=5; [[ $method == nn ]] && k=1
    "$build/apps/fovrender" --points "$set_file" --method $method --k $k --spp 4 -o "$out/f.exr" --json 2>/dev/null |
      python3 -c 'import json,sys; print("fovrender", sys.argv[1], json.load(sys.stdin)["reconstruct_ms"])' $method >> "$out/times"
    "$build/apps/fovbench" --display fove --points-dir "$out/sets" --scales 1.0 --methods $method --k 5 --spp 4 \
        --gazes centre --frames 1 --reference-spp 8 --no-flip -o "$out/bench-$rep-$method" >/dev/null 2>&1
    python3 -c 'import csv,sys; r=list(csv.DictReader(open(sys.argv[1])))[0]; print("fovbench", r["method"], r["reconstruct_ms"])' \
        "$out/bench-$rep-$method/results.csv" >> "$out/times"
  done
done
python3 - "$out/times" <<'PY'
import sys, statistics
rows = [l.split() for l in open(sys.argv[1])]
print("| method | fovrender reconstruct_ms: median (min-max) | fovbench reconstruct_ms: median (min-max) | ratio of medians |")
print("|---|---:|---:|---:|")
for m in ["nn", "shepard", "rbf"]:
    t = {tool: [float(v) for tl, mm, v in rows if tl == tool and mm == m] for tool in ("fovrender", "fovbench")}
    cell = lambda v: f"{statistics.median(v):.1f} ({min(v):.1f}-{max(v):.1f})"
    print(f"| {m} | {cell(t['fovrender'])} | {cell(t['fovbench'])} | {statistics.median(t['fovbench']) / statistics.median(t['fovrender']):.2f} |")
print(f"\n{len(rows) // 6} rounds, each tool run once per method per round, interleaved.")
PY
