#!/usr/bin/env bash
# fovgen's command line: bad flags give one line and exit 2, bad files exit 1,
# nothing half-written is left, and info --json has the documented keys.
set -uo pipefail
fovgen=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
tool=fovgen
source "$(dirname "$0")/cli_check.sh"

small=(--width 48 --height 40 --saturation 500)
check "k zero"            2 -- "$fovgen" "${small[@]}" --k 0 -o "$dir/a.fovset"
check "k too large"       2 -- "$fovgen" "${small[@]}" --k 33 -o "$dir/a.fovset"
check "width zero"        2 -- "$fovgen" --width 0 -o "$dir/a.fovset"
check "height negative"   2 -- "$fovgen" --height -5 -o "$dir/a.fovset"
check "v zero"            2 -- "$fovgen" "${small[@]}" -v 0 -o "$dir/a.fovset"
check "v huge"            2 -- "$fovgen" "${small[@]}" -v 1e300 -o "$dir/a.fovset"
err=$("$fovgen" "${small[@]}" -v 1e300 -o "$dir/a.fovset" 2>&1)
(( ${#err} < 200 )) || fail "-v 1e300 printed ${#err} characters: $err"
check "s negative"        2 -- "$fovgen" "${small[@]}" --scale -1 -o "$dir/a.fovset"
check "unknown display"   2 -- "$fovgen" --display oculus -o "$dir/a.fovset"
check "display side"      2 -- "$fovgen" --display 7x40 -o "$dir/a.fovset"
check "display fov"       2 -- "$fovgen" --display 48x40@180deg -o "$dir/a.fovset"
check "display ppd"       2 -- "$fovgen" --display 48x40@-2ppd -o "$dir/a.fovset"
check "display distance"  2 -- "$fovgen" --display 48x40@5000 -o "$dir/a.fovset"
# A table that cannot fit is refused before any dart (8192 x 8192 at k = 32: 34.4 GB).
memory_kb=$(awk '/^MemTotal:/ {print $2}' /proc/meminfo)
if (( memory_kb < 33000000 )); then
  check "display too large" 2 -- "$fovgen" --display 8192x8192 --k 32 -o "$dir/a.fovset"
else
  echo "SKIP display too large: this machine holds an 8192 x 8192 set's table"
fi
[[ ! -e "$dir/a.fovset" ]] || fail "a refused display wrote a set"
check "unknown encoding"  2 -- "$fovgen" "${small[@]}" --encoding lzma -o "$dir/a.fovset"
check "unwritable output" 2 -- "$fovgen" "${small[@]}" -o "$dir/no/such/dir/a.fovset"
check "missing output"    2 -- "$fovgen" "${small[@]}"
check "not a number"      2 -- "$fovgen" --width abc -o "$dir/a.fovset"
check "unknown flag"      2 -- "$fovgen" --frobnicate
check "unknown fovea"     2 -- "$fovgen" "${small[@]}" --fovea hex -o "$dir/a.fovset"
check "grid spacing low"  2 -- "$fovgen" "${small[@]}" --fovea grid --grid-spacing 0.1 -o "$dir/a.fovset"
check "grid spacing nan"  2 -- "$fovgen" "${small[@]}" --fovea grid --grid-spacing nan -o "$dir/a.fovset"
check "grid spacing, darts" 2 -- "$fovgen" "${small[@]}" --grid-spacing 2 -o "$dir/a.fovset"
check "k above points"    2 -- "$fovgen" --width 1 --height 1 --k 20 -o "$dir/one.fovset"
[[ -e "$dir/one.fovset" ]] && { echo "FAIL a failed generation left its output"; failures=$((failures + 1)); }

check "generate"          0 -- "$fovgen" "${small[@]}" --k 8 -o "$dir/a.fovset"
check "generate 1x1"      0 -- "$fovgen" --width 1 --height 1 --k 1 -o "$dir/one.fovset"
check "info"              0 -- "$fovgen" info "$dir/a.fovset"
mv "$dir/a.fovset.gen.json" "$dir/gen.json.saved" && mkdir "$dir/a.fovset.gen.json"
check "sidecar a directory" 0 -- "$fovgen" info "$dir/a.fovset"
rmdir "$dir/a.fovset.gen.json" && mv "$dir/gen.json.saved" "$dir/a.fovset.gen.json"
check "bad gaze"          2 -- "$fovgen" info "$dir/a.fovset" --gaze 10
check "gaze off screen"   2 -- "$fovgen" info "$dir/a.fovset" --gaze 100,10
check "plot"              0 -- "$fovgen" plot "$dir/a.fovset" --gaze 10,30 -o "$dir/p.png"
check "info missing file" 1 -- "$fovgen" info "$dir/missing.fovset"
head -c 1000 "$dir/a.fovset" > "$dir/cut.fovset"
check "info truncated"    1 -- "$fovgen" info "$dir/cut.fovset"
printf 'hello' > "$dir/text.fovset"
check "info not a set"    1 -- "$fovgen" info "$dir/text.fovset"
check "sweep bad scales"  2 -- "$fovgen" sweep "${small[@]}" --scales 2:1:0.1 -o "$dir/sweep"
check "sweep"             0 -- "$fovgen" sweep "${small[@]}" --k 4 --scales 1.0,1.5 -o "$dir/sweep"
[[ -s "$dir/sweep/48x40-v1-s1.50.fovset" && -s "$dir/sweep/point-counts.csv" && -s "$dir/sweep/point-counts.png" && -s "$dir/sweep/point-counts.svg" ]] \
  || { echo "FAIL sweep outputs missing: $(ls "$dir/sweep")"; failures=$((failures + 1)); }
check "sweep other k"     0 -- "$fovgen" sweep "${small[@]}" --k 6 --scales 1.0,1.5 --skip-existing -o "$dir/sweep"
"$fovgen" info "$dir/sweep/48x40-v1-s1.00.fovset" --json | grep -q '"k": 6,' \
  || { echo "FAIL --skip-existing kept a set made with another --k"; failures=$((failures + 1)); }

# Displays by pixels per degree and field of view, named the one way every tool names them.
"$fovgen" --display 48x40@30ppd --saturation 500 --k 4 -o "$dir/ppd.fovset" >/dev/null || fail "--display 48x40@30ppd"
ppd_json=$("$fovgen" info "$dir/ppd.fovset" --json)
python3 - "$ppd_json" <<'PY' || fail "info --json of a 30 ppd display: $ppd_json"
import json, math, sys
j = json.loads(sys.argv[1])
assert abs(j["pixels_per_degree"] - 30) < 1e-9, j
assert j["display"] == "48x40-v%.4g" % (30 * 180 / (math.pi * 48)), j
assert abs(j["viewing_distance"] - 30 * 180 / (math.pi * 48)) < 1e-9, j
PY
check "sweep by display spec" 0 -- "$fovgen" sweep --display 48x40@60deg --saturation 500 --k 4 --scales 1.0 -o "$dir/specs"
ls "$dir/specs"/48x40-v0.866-s1.00.fovset >/dev/null 2>&1 || fail "a 60-degree 48x40 display's set is not 48x40-v0.866-s1.00.fovset: $(ls "$dir/specs")"

json=$("$fovgen" info "$dir/a.fovset" --gaze 24,20 --json)
for key in width height viewing_distance scale k seed points_total spacing_violations generation_seconds points_traced; do
  if ! grep -q "\"$key\":" <<<"$json"; then echo "FAIL info --json lacks $key"; failures=$((failures + 1)); fi
done
grep -q '"spacing_violations": 0,' <<<"$json" || { echo "FAIL spacing violations not 0"; failures=$((failures + 1)); }
[[ $(head -c 8 "$dir/p.png" | od -An -c | tr -d ' ') == "211PNG\r\n032\n" ]] || { echo "FAIL plot is not a PNG"; failures=$((failures + 1)); }

# Issue 24: a cells set keeps the points only on disk and finds the table's neighbours at
# load: the same points traced from a file of the points alone. (Memory: at this size the
# points are as dense as pixels and the cells take more than the table; knn_cells_test.)
check "generate cells"    0 -- "$fovgen" "${small[@]}" --k 8 --encoding cells -o "$dir/c.fovset"
python3 - "$("$fovgen" info "$dir/a.fovset" --gaze 24,20 --json)" "$("$fovgen" info "$dir/c.fovset" --gaze 24,20 --json)" <<'PY' \
  || fail "a cells set's info differs from the table set's as it should not"
import json, sys
a, c = json.loads(sys.argv[1]), json.loads(sys.argv[2])
assert a["neighbours"] == "table" and c["neighbours"] == "cells", (a["neighbours"], c["neighbours"])
assert a["k"] == c["k"] and a["points_total"] == c["points_total"], (a["k"], c["k"])
assert a["points_traced"] == c["points_traced"], (a["points_traced"], c["points_traced"])
assert c["file_bytes"] == 512 + 12 * c["points_total"], c["file_bytes"]
assert c["knn_memory_bytes"] > 0 and a["knn_memory_bytes"] == 4 * 96 * 80 * 8, (c, a)
PY
check "sweep cells"       0 -- "$fovgen" sweep "${small[@]}" --k 4 --scales 1.0 --encoding cells --skip-existing -o "$dir/cellsweep"
"$fovgen" info "$dir/cellsweep/48x40-v1-s1.00.fovset" --json | grep -q '"neighbours": "cells",' || fail "a cells sweep wrote a table set"

# A grid fovea: a partial grid (N v = 1280 as on a FOVE, thinned by s = 4), reported by info.
check "generate grid"     0 -- "$fovgen" --width 128 --height 96 -v 10 --scale 4 --saturation 500 --k 8 --fovea grid -o "$dir/g.fovset"
grid_json=$("$fovgen" info "$dir/g.fovset" --json)
grep -q '"fovea": "grid",' <<<"$grid_json" || fail "info --json lacks fovea grid"
grid_points=$(grep -o '"grid_points": [0-9]*' <<<"$grid_json" | grep -o '[0-9]*$')
[[ ${grid_points:-0} -gt 5000 && ${grid_points:-0} -lt 24576 ]] || fail "grid points $grid_points, not a partial grid"
grep -q '"spacing_violations": 0,' <<<"$grid_json" || fail "grid set has spacing violations"
"$fovgen" info "$dir/a.fovset" --json | grep -q '"fovea": "darts",' || fail "the default fovea is not darts"
"$fovgen" --width 128 --height 96 -v 10 --scale 4 --saturation 500 --k 8 --fovea grid -o "$dir/g2.fovset" >/dev/null
cmp -s "$dir/g.fovset" "$dir/g2.fovset" || fail "same grid flags, different bytes"

check "sweep grid"        0 -- "$fovgen" sweep "${small[@]}" --k 4 --scales 1.0 --fovea grid -o "$dir/sweep"
[[ -s "$dir/sweep/48x40-v1-s1.00-grid.fovset" ]] || fail "a grid sweep did not name its set -grid"
"$fovgen" info "$dir/sweep/48x40-v1-s1.00.fovset" --json | grep -q '"fovea": "darts",' || fail "a grid sweep replaced the darts set"
check "sweep grid 1.5"    0 -- "$fovgen" sweep "${small[@]}" --k 4 --scales 1.0 --fovea grid --grid-spacing 1.5 -o "$dir/sweep"
[[ -s "$dir/sweep/48x40-v1-s1.00-grid-1.50.fovset" ]] || fail "a grid sweep at another spacing did not name its set -grid-1.50"

"$fovgen" "${small[@]}" --k 8 --seed 3 -o "$dir/x.fovset" >/dev/null
"$fovgen" "${small[@]}" --k 8 --seed 3 -o "$dir/y.fovset" >/dev/null
cmp -s "$dir/x.fovset" "$dir/y.fovset" || { echo "FAIL same seed, different bytes"; failures=$((failures + 1)); }
ls "$dir" | grep -q 'tmp-' && { echo "FAIL temporary files left: $(ls "$dir")"; failures=$((failures + 1)); }

# info and plot check the whole file, the neighbour table too: a table index flipped past
# the point count (checksums made right again) is refused as fovrender refuses it.
cp "$dir/a.fovset" "$dir/flipped.fovset"
python3 - "$dir/flipped.fovset" <<'PY'
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
b[-8:] = b"\xff" * 8  # the last table chunk's bytes (its checksum then fails)
open(sys.argv[1], "wb").write(b)
PY
check "info bad table"    1 -- "$fovgen" info "$dir/flipped.fovset"
check "plot bad table"    1 -- "$fovgen" plot "$dir/flipped.fovset" -o "$dir/flipped.png"
[[ ! -e "$dir/flipped.png" ]] || fail "plot wrote a PNG of a corrupt set"
check "info k zero"       2 -- "$fovgen" info "$dir/a.fovset" --gaze centre --k 0
check "info k above"      2 -- "$fovgen" info "$dir/a.fovset" --gaze centre --k 9
check "plot k above"      2 -- "$fovgen" plot "$dir/a.fovset" --gaze centre --k 9 -o "$dir/k.png"

# Outputs: the input itself, a link, a device, a directory are refused before any work,
# and nothing is replaced; a temporary file a killed fovgen left is removed by the next run.
cp "$dir/a.fovset" "$dir/keep.fovset"
check "plot over its input" 2 -- "$fovgen" plot "$dir/keep.fovset" -o "$dir/keep.fovset"
cmp -s "$dir/a.fovset" "$dir/keep.fovset" || fail "plot -o its input changed the input"
ln -s "$dir/keep.fovset" "$dir/link.fovset"
check "output a symlink"  2 -- "$fovgen" "${small[@]}" -o "$dir/link.fovset"
[[ -L "$dir/link.fovset" ]] || fail "a symlink output was replaced"
check "output a device"   2 -- "$fovgen" "${small[@]}" -o /dev/null
[[ -c /dev/null ]] || fail "/dev/null is no longer a device"
check "output a directory" 2 -- "$fovgen" "${small[@]}" -o "$dir"
( sleep 0 ) & dead=$!; wait $dead
echo "left by kill -9" > "$dir/b.fovset.tmp-$dead-Xy12Zw"
"$fovgen" "${small[@]}" -o "$dir/b.fovset" >/dev/null 2>"$dir/b.err" || fail "generate beside a stale temp: $(cat "$dir/b.err")"
[[ ! -e "$dir/b.fovset.tmp-$dead-Xy12Zw" ]] || fail "a stale temporary file was not removed"
grep -q "removed .*b.fovset.tmp-$dead-Xy12Zw" "$dir/b.err" || fail "the stale temporary file's removal was not reported"

# Nested sets (--levels): bad scales are flags (exit 2), nothing written.
check "levels one"        2 -- "$fovgen" "${small[@]}" --levels 1.0 -o "$dir/n.fovset"
check "levels decreasing" 2 -- "$fovgen" "${small[@]}" --levels 2.0,1.0 -o "$dir/n.fovset"
check "levels equal"      2 -- "$fovgen" "${small[@]}" --levels 1.0,1.0 -o "$dir/n.fovset"
check "levels zero"       2 -- "$fovgen" "${small[@]}" --levels 0,1.0 -o "$dir/n.fovset"
check "levels text"       2 -- "$fovgen" "${small[@]}" --levels 1.0,x -o "$dir/n.fovset"
check "levels nine"       2 -- "$fovgen" "${small[@]}" --levels 1,2,3,4,5,6,7,8,9 -o "$dir/n.fovset"
check "levels and scale"  2 -- "$fovgen" "${small[@]}" --levels 1.0,2.0 --scale 1.5 -o "$dir/n.fovset"
check "levels and grid"   2 -- "$fovgen" "${small[@]}" --levels 1.0,2.0 --fovea grid -o "$dir/n.fovset"
[[ ! -e "$dir/n.fovset" ]] || fail "a refused --levels left a file"
check "levels"            0 -- "$fovgen" "${small[@]}" --k 4 --levels 1.0,2.0,3.0 -o "$dir/n.fovset"
"$fovgen" info "$dir/n.fovset" --json > "$dir/n.json" || fail "info on a nested set"
python3 - "$dir/n.json" <<'PY' || fail "info --json levels"
import json, sys
j = json.load(open(sys.argv[1]))
levels = j["levels"]
assert [l["scale"] for l in levels] == [3.0, 2.0, 1.0], levels
assert all(l["spacing_violations"] == 0 for l in levels), levels
assert levels[-1]["points"] == j["points_total"] and j["scale"] == 1.0, j
assert all(a["points"] < b["points"] for a, b in zip(levels, levels[1:])), levels
PY

# Issue 27: acuity models. Bad models and parameters are flags (exit 2), nothing written;
# a model's set is named by it and info --json reports the model, its parameters, the sampler.
check "unknown acuity"    2 -- "$fovgen" "${small[@]}" --acuity cortical -o "$dir/m.fovset"
check "mar slope zero"    2 -- "$fovgen" "${small[@]}" --acuity linear-mar --mar-slope 0 -o "$dir/m.fovset"
check "mar slope nan"     2 -- "$fovgen" "${small[@]}" --acuity linear-mar --mar-slope nan -o "$dir/m.fovset"
check "mar fovea big"     2 -- "$fovgen" "${small[@]}" --acuity linear-mar --mar-fovea 2 -o "$dir/m.fovset"
check "mar dead zone"     2 -- "$fovgen" "${small[@]}" --acuity linear-mar --mar-dead-zone -1 -o "$dir/m.fovset"
check "mar, csf"          2 -- "$fovgen" "${small[@]}" --mar-slope 0.03 -o "$dir/m.fovset"
check "pivots, linear"    2 -- "$fovgen" "${small[@]}" --acuity linear-mar --acuity-pivots 40,10,6,5,4 -o "$dir/m.fovset"
check "pivots four"       2 -- "$fovgen" "${small[@]}" --acuity piecewise-mar --acuity-pivots 40,10,6,5 -o "$dir/m.fovset"
check "pivots growing"    2 -- "$fovgen" "${small[@]}" --acuity piecewise-mar --acuity-pivots 40,10,12,5,4 -o "$dir/m.fovset"
check "pivots zero"       2 -- "$fovgen" "${small[@]}" --acuity piecewise-mar --acuity-pivots 40,10,6,5,0 -o "$dir/m.fovset"
[[ ! -e "$dir/m.fovset" ]] || fail "a refused acuity model left a file"
for model in linear-mar piecewise-mar; do
  check "sweep $model"    0 -- "$fovgen" sweep "${small[@]}" --k 4 --scales 1.0 --acuity $model -o "$dir/models"
  [[ -s "$dir/models/48x40-v1-$model-s1.00.fovset" ]] || fail "a $model set is not named 48x40-v1-$model-s1.00.fovset: $(ls "$dir/models")"
done
"$fovgen" info "$dir/models/48x40-v1-piecewise-mar-s1.00.fovset" --json > "$dir/m.json" || fail "info on a piecewise-mar set"
python3 - "$dir/m.json" <<'PY' || fail "info --json of a piecewise-mar set"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["acuity"] == "piecewise-mar" and j["sampler"] == "poisson", j
assert [p["cpd"] for p in j["acuity_params"]["pivots"]] == [40, 10, 6, 5, 4], j["acuity_params"]
assert j["spacing_violations"] == 0, j
PY
"$fovgen" info "$dir/a.fovset" --json | grep -q '"acuity": "csf",' || fail "a default set's acuity is not csf"
check "acuity table"      0 -- "$fovgen" acuity --display 48x40 -o "$dir/acuity"
[[ -s "$dir/acuity.png" && -s "$dir/acuity.svg" ]] || fail "fovgen acuity -o wrote no figure"
[[ $("$fovgen" acuity --display fove | grep -c '^linear-mar,') -eq 401 ]] || fail "fovgen acuity: not 401 linear-mar rows"
check "acuity bad display" 2 -- "$fovgen" acuity --display oculus
check "acuity bad scale"  2 -- "$fovgen" acuity --scale -1

# Samplers: a lattice has no grid fovea and no levels; its set is named by it.
check "unknown sampler"   2 -- "$fovgen" "${small[@]}" --sampler hex -o "$dir/m.fovset"
check "sampler and grid"  2 -- "$fovgen" "${small[@]}" --sampler polar --fovea grid -o "$dir/m.fovset"
check "sampler, levels"   2 -- "$fovgen" "${small[@]}" --sampler log-polar --levels 1.0,2.0 -o "$dir/m.fovset"
[[ ! -e "$dir/m.fovset" ]] || fail "a refused sampler left a file"
check "sweep polar"       0 -- "$fovgen" sweep "${small[@]}" --k 4 --scales 1.0 --acuity linear-mar --sampler polar -o "$dir/models"
[[ -s "$dir/models/48x40-v1-linear-mar-polar-s1.00.fovset" ]] || fail "a polar set is not named ...-linear-mar-polar-s1.00: $(ls "$dir/models")"
check "generate log-polar" 0 -- "$fovgen" "${small[@]}" --k 4 --sampler log-polar -o "$dir/lp.fovset"
"$fovgen" "${small[@]}" --k 4 --sampler log-polar -o "$dir/lp2.fovset" | grep -q "points placed by the log-polar lattice" \
  || fail "generating a lattice set does not say so"
"$fovgen" info "$dir/models/48x40-v1-linear-mar-polar-s1.00.fovset" --json > "$dir/p.json" || fail "info on a polar set"
python3 - "$dir/p.json" <<'PY' || fail "info --json of a polar set"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["sampler"] == "polar" and j["acuity"] == "linear-mar", j
assert j["spacing_violations"] is None, j  # the darts' rule; a lattice keeps its pitch on average
PY

echo "fovgen CLI: $passes passed, $failures failed"
[[ $failures -eq 0 ]]
