#!/usr/bin/env bash
# Points per scheme (issue 27, docs/schemes.md): for each ACUITY:SAMPLER, a set at s = 1 on each
# headset preset and on a ladder of displays of the FOVE's field of view at growing pixels per
# degree; prints a CSV of the points in the set, on the screen and traced for a centred gaze
# (k = 5, fovrender's default), and the seconds fovgen took (from its sidecar).
# Usage: scripts/scheme-counts.sh OUT_DIR [ACUITY:SAMPLER...] (default: every acuity model with
# darts, then the papers' pairs linear-mar:polar and piecewise-mar:log-polar)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:?usage: scheme-counts.sh OUT_DIR [ACUITY:SAMPLER...]}
shift
schemes=("$@")
(( ${#schemes[@]} )) || schemes=(csf:poisson linear-mar:poisson piecewise-mar:poisson linear-mar:polar piecewise-mar:log-polar)
fovgen=${FOV_BUILD:-$root/build}/apps/fovgen
mkdir -p "$out"
# The ladder: the FOVE's field of view (53.13 x 58.72 degrees; a WxH display is seen from one
# width, v = 1) at 33.5, 44.7 and 67 pixels per degree.
displays=(fove vive quest3 vision-pro varjo-xr4 retinal 1920x2160 2560x2880 3840x4320)
echo "acuity,sampler,display,pixels_per_degree,points_total,points_on_screen,points_traced_centre,generation_seconds"
for scheme in "${schemes[@]}"; do
  model=${scheme%%:*} sampler=${scheme#*:}
  for d in "${displays[@]}"; do
    flags=(--display "$d" --acuity "$model" --sampler "$sampler" --k 5 --encoding cells)
    set_path="$out/$d-$model.fovset"
    [[ $sampler == poisson ]] || set_path="$out/$d-$model-$sampler.fovset"
    [[ -s $set_path ]] || "$fovgen" "${flags[@]}" -o "$set_path" > /dev/null
    "$fovgen" info "$set_path" --gaze centre --k 5 --json | python3 -c '
import json, sys
j = json.load(sys.stdin)
keys = ("display", "pixels_per_degree", "points_total", "points_on_screen", "points_traced", "generation_seconds")
print(",".join(sys.argv[1:3] + ["%.1f" % j[k] if k in ("pixels_per_degree", "generation_seconds") else str(j[k]) for k in keys]))
' "$model" "$sampler"
  done
done
