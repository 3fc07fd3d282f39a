#!/usr/bin/env bash
# Regenerates the point sets of this folder (see README.md here).
#   generate.sh default     the FOVE s = 1.0 set (about 20 s on 2 cores)
#   generate.sh staircase   the 21-set staircase family s = 1.0 .. 3.0 (about 5 min)
#   generate.sh bench       the sets the benchmarks read: s = 1.0 and 1.75, darts and grid fovea
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
fovgen=${FOVGEN:-$here/../build/apps/fovgen}
[[ -x "$fovgen" ]] || { echo "generate.sh: $fovgen not built; run scripts/build.sh first" >&2; exit 1; }
case "${1:-default}" in
  default)   "$fovgen" --display fove --scale 1.0 --k 20 --seed 1 -o "$here/fove-s1.00.fovset" ;;
  bench)     for s in 1.00 1.75; do
               "$fovgen" --display fove --scale $s --k 20 --seed 1 -o "$here/fove-s$s.fovset"
               "$fovgen" --display fove --scale $s --k 20 --seed 1 --fovea grid -o "$here/fove-s$s-grid.fovset"
             done ;;
  staircase) "$fovgen" sweep --display fove --k 20 --seed 1 --scales 1.0:3.0:0.1 --skip-existing -o "$here" ;;
  *) echo "generate.sh: unknown target '$1' (default, bench, staircase)" >&2; exit 2 ;;
esac
