#!/usr/bin/env bash
# Checks and times the reconstruction and TAA kernels on the first OpenCL device this
# machine offers (PoCL here; a GPU where one is installed): the tests that hold the kernels
# to the C++ path (cl_reconstruct_tests, OpenCL required), then reconstruct_bench on the
# FOVE s = 1.0 table set (every method, k and path) and on each .fovset named (the device's
# rows at k = 5). Needs only the two test programs, so it runs on a machine that has the
# OpenCL loader and a driver but not the rest of the build's libraries.
#
#   scripts/device-kernels.sh OUT [SET.fovset ...]
#
# FOV_BUILD: the folder holding tests/cl_reconstruct_tests and tests/reconstruct_bench
# (default build). FOV_BENCH_REPS: repetitions of each benchmark (default 3).
# Writes OUT/cl_reconstruct_tests.log, OUT/bench-fove-table.json and
# OUT/bench-NAME.json per set, and OUT/summary.md (scripts/device_kernels_table.py).
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: scripts/device-kernels.sh OUT [SET.fovset ...]" >&2
  exit 2
fi
out=$1
shift
build=${FOV_BUILD:-build}
reps=${FOV_BENCH_REPS:-3}
for set in "$@"; do
  [[ -r "$set" ]] || { echo "scripts/device-kernels.sh: $set: cannot be read" >&2; exit 2; }
done
for program in cl_reconstruct_tests reconstruct_bench; do
  [[ -x "$build/tests/$program" ]] || { echo "scripts/device-kernels.sh: $build/tests/$program missing (build first, or set FOV_BUILD)" >&2; exit 2; }
done
[[ "$reps" =~ ^[1-9][0-9]?$ ]] || { echo "scripts/device-kernels.sh: FOV_BENCH_REPS=$reps: want 1..99" >&2; exit 2; }
mkdir -p "$out"
here=$(cd "$(dirname "$0")" && pwd)

FOV_REQUIRE_OPENCL=1 "$build/tests/cl_reconstruct_tests" --gtest_brief=1 2>&1 | tee "$out/cl_reconstruct_tests.log"

bench() {  # NAME FILTER [SET]
  local name=$1 filter=$2
  shift 2
  (if [[ $# -gt 0 ]]; then export FOV_BENCH_SET=$1; fi
   "$build/tests/reconstruct_bench" --benchmark_filter="$filter" --benchmark_repetitions="$reps" \
     --benchmark_out="$out/bench-$name.json" --benchmark_out_format=json)
}
bench fove-table '.'
for set in "$@"; do
  bench "$(basename "$set" .fovset)" 'BM_Reconstruct/method:[012]/k:5/opencl:1|BM_ReconstructTaa' "$set"
done
python3 "$here/device_kernels_table.py" "$out"/bench-*.json > "$out/summary.md"
cat "$out/summary.md"
