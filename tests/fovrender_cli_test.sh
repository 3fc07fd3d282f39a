#!/usr/bin/env bash
# fovrender's command line: bad flags give one line and exit 2, bad files exit 1, and
# a small render, its reference and the comparison work end to end.
set -uo pipefail
fovrender=$1
fovgen=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
tool=fovrender
source "$(dirname "$0")/cli_check.sh"

"$fovgen" --width 64 --height 72 --k 8 --saturation 500 -o "$dir/set.fovset" >/dev/null
set=(--points "$dir/set.fovset")
check "no points"          2 -- "$fovrender" -o "$dir/a.png"
check "nothing to do"      2 -- "$fovrender" "${set[@]}"
check "unknown method"     2 -- "$fovrender" "${set[@]}" --method cubic -o "$dir/a.png"
check "k above the set"    2 -- "$fovrender" "${set[@]}" --k 9 -o "$dir/a.png"
check "spp zero"           2 -- "$fovrender" "${set[@]}" --spp 0 -o "$dir/a.png"
check "gaze off screen"    2 -- "$fovrender" "${set[@]}" --gaze 100,10 -o "$dir/a.png"
check "bad rbf kernel"     2 -- "$fovrender" "${set[@]}" --method rbf --rbf-kernel cubic -o "$dir/a.png"
check "bad rbf shape"      2 -- "$fovrender" "${set[@]}" --method rbf --rbf-shape -1 -o "$dir/a.png"
check "unknown integrator" 2 -- "$fovrender" "${set[@]}" --integrator photon -o "$dir/a.png"
check "bounces past 64"    2 -- "$fovrender" "${set[@]}" --integrator path --bounces 65 -o "$dir/a.png"
check "env light missing"  2 -- "$fovrender" "${set[@]}" --env-light "$dir/none.exr" -o "$dir/a.png"
check "env light not an image" 2 -- "$fovrender" "${set[@]}" --env-light "$0" -o "$dir/a.png"
[[ "$("$fovrender" "${set[@]}" --env-light "$dir/none.exr" -o "$dir/a.png" 2>&1)" == "fovrender: --env-light: $dir/none.exr: cannot open"* ]] \
  || fail "a missing --env-light image is not named with the flag"
check "rbf"                0 -- "$fovrender" "${set[@]}" --spp 2 --method rbf --k 8 -o "$dir/rbf.png"
# The Delaunay methods: at k = 8 they run; at k = 1 every pixel off a point falls back to
# Shepard's weights, which fovrender says in one line naming the method and the remedy.
check "barycentric"        0 -- "$fovrender" "${set[@]}" --spp 2 --method barycentric --k 8 -o "$dir/bary.png"
check "natural"            0 -- "$fovrender" "${set[@]}" --spp 2 --method natural --k 8 -o "$dir/natural.png"
"$fovrender" "${set[@]}" --spp 1 --method natural --k 1 -o "$dir/n1.png" --json > "$dir/n1.json" 2> "$dir/n1.err"
if [[ $(grep -c "natural fell back to Shepard at .* raise --k" "$dir/n1.err") != 1 ]] ||
   ! python3 -c 'import json, sys; d = json.load(open(sys.argv[1]))["delaunay"]; sys.exit(0 if d["fallback_beyond_k"] > 0 and d["fallbacks"] == d["fallback_beyond_k"] + d["fallback_outside_hull"] else 1)' "$dir/n1.json"; then
  echo "FAIL natural at k = 1: no single fallback line or no counts in --json"; cat "$dir/n1.err"; failures=$((failures + 1))
fi
check "footprint unknown"  2 -- "$fovrender" "${set[@]}" --texture-footprint wide -o "$dir/a.png"
check "pixel footprint"    0 -- "$fovrender" "${set[@]}" --spp 2 --texture-footprint pixel -o "$dir/px.png"
check "bad device"         2 -- "$fovrender" "${set[@]}" --device tpu -o "$dir/a.png"
check "cpp device"         0 -- "$fovrender" "${set[@]}" --spp 2 --device cpp -o "$dir/cpp.png"
check "bad debug view"     2 -- "$fovrender" "${set[@]}" --debug-view heat -o "$dir/a.png"
check "debug view no out"  2 -- "$fovrender" "${set[@]}" --debug-view points --compare "$dir/ref.exr"
for view in points density eccentricity; do
  check "debug $view"      0 -- "$fovrender" "${set[@]}" --spp 1 --debug-view $view -o "$dir/d.png"
  [[ -s "$dir/d-$view.png" ]] || { echo "FAIL --debug-view $view wrote no d-$view.png"; failures=$((failures + 1)); }
done
# --ray-floor: with --reference the full grid's rays fall, with --points each point's (the
# set's own model: seen from 10 screen widths at scale 4 its spacing grows across the screen).
"$fovgen" --display 128x96@10 --scale 4 --k 8 --saturation 500 -o "$dir/ppd.fovset" >/dev/null
check "ray floor above spp" 2 -- "$fovrender" "${set[@]}" --spp 2 --ray-floor 3 -o "$dir/a.png"
check "ray floor zero"     2 -- "$fovrender" "${set[@]}" --spp 2 --ray-floor 0 -o "$dir/a.png"
check "scale with points"  2 -- "$fovrender" "${set[@]}" --spp 4 --ray-floor 1 --falloff-scale 2 -o "$dir/a.png"
check "falloff reference"  0 -- "$fovrender" --reference --display 96x96@60ppd --spp 4 --ray-floor 1 -o "$dir/fall.png"
python3 - "$fovrender" "$dir" <<'PY' || { echo "FAIL --ray-floor with --points"; failures=$((failures + 1)); }
import json, subprocess, sys
run = lambda *a: json.loads(subprocess.run([sys.argv[1], "--points", sys.argv[2] + "/ppd.fovset", "--spp", "4", "--json",
                                            "--device", "cpp", *a], check=True, capture_output=True, text=True).stdout)
flat, fall = run("-o", sys.argv[2] + "/flat.png"), run("--ray-floor", "1", "-o", sys.argv[2] + "/pfall.png")
assert flat["points_traced"] == fall["points_traced"] and flat["rays"] == 4 * flat["points_traced"], (flat, fall)
assert fall["points_traced"] <= fall["rays"] < flat["rays"] and fall["ray_floor"] == 1 and "ray_floor" not in flat, fall
PY
# --reference --taa-frames: the full grid's steady state (mirrored patterns: each pixel's next
# Sobol samples), against a converged reference closer than one frame.
python3 - "$fovrender" "$dir" <<'PY' || { echo "FAIL --reference --taa-frames"; failures=$((failures + 1)); }
import json, subprocess, sys
run = lambda *a: json.loads(subprocess.run([sys.argv[1], "--reference", "--display", "96x96@20ppd", "--spp", "1", "--json",
                                            "--reference-spp", "64", "--no-flip", *a], check=True, capture_output=True,
                                           text=True).stdout)
one, steady = run("-o", sys.argv[2] + "/r1.png"), run("--taa-frames", "8", "--pattern", "mirror", "-o", sys.argv[2] + "/r8.png")
assert one["taa_ms"] is None and "taa_frames" not in one, one
assert steady["taa_frames"] == 8 and steady["pattern"] == "mirror" and steady["taa_ms"] > 0 and steady["rays"] == one["rays"], steady
assert steady["metrics"]["psnr"] > one["metrics"]["psnr"] + 1, (steady["metrics"]["psnr"], one["metrics"]["psnr"])
PY
check "taa frames"         0 -- "$fovrender" "${set[@]}" --spp 2 --taa-frames 4 -o "$dir/taa.png"
check "mirrored patterns"  0 -- "$fovrender" "${set[@]}" --spp 2 --taa-frames 4 --pattern mirror -o "$dir/taa-m.png"
check "bad pattern"        2 -- "$fovrender" "${set[@]}" --spp 2 --taa-frames 4 --pattern spiral -o "$dir/taa-m.png"
"$fovrender" "${set[@]}" --spp 2 --taa-frames 3 -o "$dir/taa3.png" --json | grep -q '"taa_ms": [0-9]' \
  || { echo "FAIL --taa-frames did not report taa_ms"; failures=$((failures + 1)); }
check "bad hfov"           2 -- "$fovrender" "${set[@]}" --hfov 200 -o "$dir/a.png"
check "nan hfov"           2 -- "$fovrender" "${set[@]}" --hfov nan -o "$dir/a.png"
check "bad eye"            2 -- "$fovrender" "${set[@]}" --eye 1,2 -o "$dir/a.png"
check "target is the eye"  2 -- "$fovrender" "${set[@]}" --eye 0,1,4 --look-at 0,1,4 -o "$dir/a.png"
check "up along the view"  2 -- "$fovrender" "${set[@]}" --look-at 0,100,4 -o "$dir/a.png"
check "zero up"            2 -- "$fovrender" "${set[@]}" --up 0,0,0 -o "$dir/a.png"
check "missing camera"     1 -- "$fovrender" "${set[@]}" --camera "$dir/none.csv" -o "$dir/a.png"
printf 't_ms,x,y,z,tx,ty,tz\n0,3,2,5,0,0.5,-3\n1000,0,0,0,1,0,0\n' > "$dir/path.csv"
check "camera file"        0 -- "$fovrender" "${set[@]}" --spp 1 --camera "$dir/path.csv" -o "$dir/cam-file.png"
check "eye and target"     0 -- "$fovrender" "${set[@]}" --spp 1 --eye 3,2,5 --look-at 0,0.5,-3 -o "$dir/cam-flags.png"
cmp -s "$dir/cam-file.png" "$dir/cam-flags.png" || fail "--camera FILE (first row) differs from the same --eye/--look-at"
check "default camera"     0 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir/cam-default.png"
cmp -s "$dir/cam-file.png" "$dir/cam-default.png" && fail "--eye/--look-at changed nothing"
# A time on the path and a rolling display (docs/reuse.md).
check "camera time no path" 2 -- "$fovrender" "${set[@]}" --camera-time 5 -o "$dir/a.png"
check "camera time nan"    2 -- "$fovrender" "${set[@]}" --camera "$dir/path.csv" --camera-time nan -o "$dir/a.png"
check "rolling unknown"    2 -- "$fovrender" "${set[@]}" --camera "$dir/path.csv" --rolling sideways -o "$dir/a.png"
check "rolling no path"    2 -- "$fovrender" "${set[@]}" --rolling top-down -o "$dir/a.png"
check "frame period zero"  2 -- "$fovrender" "${set[@]}" --camera "$dir/path.csv" --rolling top-down --frame-period 0 -o "$dir/a.png"
check "frame period long"  2 -- "$fovrender" "${set[@]}" --camera "$dir/path.csv" --rolling top-down --frame-period 1001 -o "$dir/a.png"
check "rolling flicker"    2 -- "$fovrender" "${set[@]}" --camera "$dir/path.csv" --rolling top-down --flicker 3 -o "$dir/a.png"
[[ -e "$dir/a.png" ]] && fail "a refused rolling run wrote its output"
check "camera time 0"      0 -- "$fovrender" "${set[@]}" --spp 1 --camera "$dir/path.csv" --camera-time 0 -o "$dir/cam-t0.png"
cmp -s "$dir/cam-file.png" "$dir/cam-t0.png" || fail "--camera-time 0 is not the path's first row"
check "camera time 500"    0 -- "$fovrender" "${set[@]}" --spp 1 --camera "$dir/path.csv" --camera-time 500 -o "$dir/cam-t500.png"
cmp -s "$dir/cam-file.png" "$dir/cam-t500.png" && fail "--camera-time 500 changed nothing"
# Temporal reuse (docs/reuse.md).
check "reuse unknown"      2 -- "$fovrender" "${set[@]}" --reuse spatial -o "$dir/a.png"
check "reuse fovea"        2 -- "$fovrender" "${set[@]}" --reuse temporal --reuse-fovea 61 -o "$dir/a.png"
check "reuse threshold"    2 -- "$fovrender" "${set[@]}" --reuse temporal --reuse-threshold 2 -o "$dir/a.png"
check "reuse max age"      2 -- "$fovrender" "${set[@]}" --reuse temporal --reuse-max-age 0 -o "$dir/a.png"
check "reuse budget"       2 -- "$fovrender" "${set[@]}" --reuse temporal --reuse-budget -1 -o "$dir/a.png"
check "reuse budget huge"  2 -- "$fovrender" "${set[@]}" --reuse temporal --reuse-budget 1099511627777 -o "$dir/a.png"
check "reuse view"         2 -- "$fovrender" "${set[@]}" --reuse temporal --reuse-view 181 -o "$dir/a.png"
check "reuse edges"        2 -- "$fovrender" "${set[@]}" --reuse temporal --reuse-edges loose -o "$dir/a.png"
check "reuse distance"     2 -- "$fovrender" "${set[@]}" --reuse temporal --reuse-distance far -o "$dir/a.png"
check "reuse reference"    2 -- "$fovrender" --reference --width 32 --height 24 --reuse temporal -o "$dir/a.png"
check "reuse ray floor"    2 -- "$fovrender" "${set[@]}" --reuse temporal --ray-floor 1 -o "$dir/a.png"
check "path without flicker" 2 -- "$fovrender" "${set[@]}" --flicker-yaw 1 -o "$dir/a.png"
check "path yaw too fast"  2 -- "$fovrender" "${set[@]}" --flicker 3 --flicker-yaw 11 -o "$dir/a.png"
[[ -e "$dir/a.png" ]] && fail "a refused reuse run wrote its output"
python3 - "$fovrender" "$dir" <<'PY' || { echo "FAIL --reuse temporal"; failures=$((failures + 1)); }
import json, subprocess, sys
run = lambda *a: json.loads(subprocess.run([sys.argv[1], "--points", sys.argv[2] + "/set.fovset", "--spp", "8", "--json",
                                            "--device", "cpp", "--reuse", "temporal", "--reuse-fovea", "3", *a],
                                           check=True, capture_output=True, text=True).stdout)
still = run("--taa-frames", "3", "-o", sys.argv[2] + "/reuse.png")["reuse"]  # the third frame of a still view
assert still["reused"] > 0 and still["reused"] + still["traced"] == still["points"], still
bands = still["by_eccentricity"]
assert sum(b["points"] for b in bands) == still["points"] and sum(b["reused"] for b in bands) == still["reused"], bands
path = run("--flicker", "4", "--flicker-shift", "0.02", "--reference-spp", "16", "-o", sys.argv[2] + "/reuse-path.png")["reuse_path"]
assert path["frames"] == 4 and len(path["per_frame"]) == 4 and 0 < path["rays_ratio"] < 1, path
assert 0 < path["all_rays_ratio"] < 1 and path["per_frame"][0]["reused"] == 0 and path["per_frame"][1]["reused"] > 0, path
assert all(k in path for k in ("jod_full", "jod_reuse", "jod_floor", "flicker_full", "flicker_reuse")), path
PY
# Two eyes (docs/reuse.md).
check "ipd negative"       2 -- "$fovrender" "${set[@]}" --stereo --ipd -1 -o "$dir/a.png"
check "ipd too wide"       2 -- "$fovrender" "${set[@]}" --stereo --ipd 1001 -o "$dir/a.png"
check "gaze right alone"   2 -- "$fovrender" "${set[@]}" --gaze-right 10,10 -o "$dir/a.png"
check "gaze right off"     2 -- "$fovrender" "${set[@]}" --stereo --gaze-right 65,10 -o "$dir/a.png"
check "eyes without stereo" 2 -- "$fovrender" "${set[@]}" --reuse eyes -o "$dir/a.png"
check "stereo compare"     2 -- "$fovrender" "${set[@]}" --stereo --compare "$dir/set.fovset" -o "$dir/a.png"
check "stereo speedup"     2 -- "$fovrender" "${set[@]}" --stereo --speedup 2 -o "$dir/a.png"
check "eyes rolling"       2 -- "$fovrender" "${set[@]}" --stereo --reuse eyes --camera "$dir/path.csv" --rolling top-down -o "$dir/a.png"
check "eyes ray floor"     2 -- "$fovrender" "${set[@]}" --stereo --reuse eyes --ray-floor 1 -o "$dir/a.png"
[[ -e "$dir/a.png" ]] && fail "a refused stereo run wrote its output"
python3 - "$fovrender" "$dir" <<'PY' || { echo "FAIL --stereo"; failures=$((failures + 1)); }
import json, subprocess, sys
run = lambda *a: json.loads(subprocess.run([sys.argv[1], "--points", sys.argv[2] + "/set.fovset", "--spp", "8", "--json",
                                            "--device", "cpp", "--stereo", *a],
                                           check=True, capture_output=True, text=True).stdout)
both = run("--gaze", "30,36", "--gaze-right", "26,36", "-o", sys.argv[2] + "/stereo.png")
assert both["width"] == 128 and both["eye_width"] == 64 and both["height"] == 72, both
l, r = both["eyes"]["left"], both["eyes"]["right"]
assert l["gaze"] == [30, 36] and r["gaze"] == [26, 36] and both["rays"] == l["rays"] + r["rays"], both
assert l["rays"] == 8 * l["points_traced"] and "reuse" not in r, both
eyes = run("--reuse", "eyes", "--reuse-fovea", "3", "--reference-spp", "16", "-o", sys.argv[2] + "/eyes.png")
l, r = eyes["eyes"]["left"], eyes["eyes"]["right"]
kept = r["reuse"]
assert kept["reused"] > 0 and kept["reused"] + kept["traced"] == kept["points"], kept
assert r["rays"] == kept["probe_rays"] + 8 * kept["traced"] and r["rays"] < l["rays"], eyes
assert all(0 < e["metrics"]["jod"] <= 10 and 0 < e["noise_floor"]["jod"] <= 10 for e in (l, r)), eyes
ref = run("--reference", "-o", sys.argv[2] + "/stereo-ref.png")
assert ref["width"] == 128 and ref["eyes"]["right"]["points_traced"] is None and ref["rays"] == 2 * 64 * 72 * 8, ref
PY
check "rolling"            0 -- "$fovrender" "${set[@]}" --spp 1 --camera "$dir/path.csv" --rolling bottom-up --frame-period 100 -o "$dir/roll.png"
cmp -s "$dir/cam-file.png" "$dir/roll.png" && fail "--rolling on a moving path changed nothing"
# Two eyes on one rolling panel: the left eye's columns first, then the right eye's.
check "stereo global"      0 -- "$fovrender" "${set[@]}" --spp 1 --stereo --camera "$dir/path.csv" -o "$dir/stereo-global.png"
check "stereo rolling"     0 -- "$fovrender" "${set[@]}" --spp 1 --stereo --camera "$dir/path.csv" --rolling left-right \
  --frame-period 100 --reference-spp 4 -o "$dir/stereo-roll.png"
cmp -s "$dir/stereo-global.png" "$dir/stereo-roll.png" && fail "--stereo --rolling on a moving path changed nothing"
check "bad size"           2 -- "$fovrender" --reference --width 0 -o "$dir/a.png"
check "size beyond memory" 2 -- "$fovrender" --reference --width 65536 --height 65536 -o "$dir/a.png"
check "bad display"        2 -- "$fovrender" --reference --display 64x72@ppd -o "$dir/a.png"
check "display and size"   2 -- "$fovrender" --reference --display 64x72 --width 64 -o "$dir/a.png"
check "display and set"    2 -- "$fovrender" --reference "${set[@]}" --display 64x72 -o "$dir/a.png"
check "display reference"  0 -- "$fovrender" --reference --display 40x24@30ppd --spp 1 -o "$dir/display.png"
python3 -c "
import sys, struct
b = open(sys.argv[1], 'rb').read(24)
assert struct.unpack('>II', b[16:24]) == (40, 24), b
" "$dir/display.png" || fail "--display 40x24@30ppd did not render 40 x 24"
ln -s "$dir/loop-b.gltf" "$dir/loop-a.gltf"; ln -s "$dir/loop-a.gltf" "$dir/loop-b.gltf"
check "scene a link loop"  1 -- "$fovrender" "${set[@]}" --scene "$dir/loop-a.gltf" -o "$dir/a.png"
check "missing set"        1 -- "$fovrender" --points "$dir/none.fovset" -o "$dir/a.png"
check "missing scene"      1 -- "$fovrender" "${set[@]}" --scene "$dir/none.gltf" -o "$dir/a.png"
check "unwritable output"  2 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir/no/dir/a.png"
check "reference"          0 -- "$fovrender" --reference "${set[@]}" --spp 4 -o "$dir/ref.exr"
check "foveated"           0 -- "$fovrender" "${set[@]}" --spp 4 --k 5 -o "$dir/fov.png" --compare "$dir/ref.exr"
check "nn"                 0 -- "$fovrender" "${set[@]}" --spp 4 --method nn --k 1 -o "$dir/nn.exr"
check "size mismatch"      2 -- "$fovrender" --reference --width 32 --height 32 --spp 1 --compare "$dir/ref.exr"
check "compare not image"  1 -- "$fovrender" "${set[@]}" --spp 1 --compare "$dir/set.fovset"
# Outputs that are inputs, links or devices are refused before anything is rendered; the
# reference survives; a truncated reference gives one line (OpenImageIO's first).
cp "$dir/ref.exr" "$dir/ref-copy.exr"
check "output is --compare" 2 -- "$fovrender" "${set[@]}" --spp 1 --compare "$dir/ref.exr" -o "$dir/ref.exr"
cmp -s "$dir/ref.exr" "$dir/ref-copy.exr" || fail "-o the --compare reference changed it"
check "flip map is --compare" 2 -- "$fovrender" "${set[@]}" --spp 1 --compare "$dir/ref.exr" --flip-map "$dir/ref.exr"
check "output is --points" 2 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir/set.fovset"
ln -s "$dir/fov.png" "$dir/link.png"
check "output a symlink"   2 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir/link.png"
[[ -L "$dir/link.png" ]] || fail "a symlink output was replaced"
check "output a device"    2 -- "$fovrender" "${set[@]}" --spp 1 -o /dev/null
check "output a directory" 2 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir"
rm -f "$dir/late.png"
check "bad --compare, nothing written" 1 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir/late.png" --compare "$dir/set.fovset"
[[ ! -e "$dir/late.png" ]] || fail "-o was written before --compare failed"
head -c 300 "$dir/fov.png" > "$dir/cut.png"
check "truncated reference" 1 -- "$fovrender" "${set[@]}" --spp 1 --compare "$dir/cut.png"
check "mismatch, -o"       2 -- "$fovrender" --reference --width 32 --height 32 --spp 1 --compare "$dir/ref.exr" -o "$dir/never.png"
[[ -e "$dir/never.png" ]] && { echo "FAIL -o written although --compare failed"; failures=$((failures + 1)); }
check "flip map alone"     2 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir/a.png" --flip-map "$dir/f.png"
check "no-flip and map"    2 -- "$fovrender" "${set[@]}" --spp 1 --compare "$dir/ref.exr" --no-flip --flip-map "$dir/f.png"
check "no-jod alone"       2 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir/a.png" --no-jod
check "peak alone"         2 -- "$fovrender" "${set[@]}" --spp 1 -o "$dir/a.png" --peak-luminance 200
check "no-jod and peak"    2 -- "$fovrender" "${set[@]}" --spp 1 --compare "$dir/ref.exr" --no-jod --peak-luminance 200
check "bad contrast"       2 -- "$fovrender" "${set[@]}" --spp 1 --compare "$dir/ref.exr" --contrast 1
check "flip maps"          0 -- "$fovrender" "${set[@]}" --spp 4 --compare "$dir/ref.exr" --flip-map "$dir/flip.png" \
  --foveated-flip-map "$dir/fflip.png"
[[ -s "$dir/flip.png" && -s "$dir/fflip.png" ]] || { echo "FAIL FLIP maps not written"; failures=$((failures + 1)); }
check "exposure range"     2 -- "$fovrender" "${set[@]}" --spp 1 --exposure 30 -o "$dir/a.png"
check "exposure nan"       2 -- "$fovrender" "${set[@]}" --spp 1 --exposure nan -o "$dir/a.png"
check "sun dir zero"       2 -- "$fovrender" "${set[@]}" --spp 1 --sun-dir 0,0,0 -o "$dir/a.png"
check "sun dir text"       2 -- "$fovrender" "${set[@]}" --spp 1 --sun-dir up -o "$dir/a.png"
check "sun irradiance"     2 -- "$fovrender" "${set[@]}" --spp 1 --sun-irradiance abc -o "$dir/a.png"
check "sun negative"       2 -- "$fovrender" "${set[@]}" --spp 1 --sun-irradiance -1 -o "$dir/a.png"
check "sampler"            2 -- "$fovrender" --reference "${set[@]}" --spp 1 --reference-sampler halton -o "$dir/a.png"
check "exposed, sunlit"    0 -- "$fovrender" "${set[@]}" --spp 1 --exposure -1 --sun-dir 0,1,0 --sun-irradiance 0.8 -o "$dir/sun.png"
cmp -s "$dir/sun.png" "$dir/cam-default.png" && fail "--exposure/--sun-* changed nothing"
check "weak reference"     2 -- "$fovrender" "${set[@]}" --spp 4 --reference-spp 4 -o "$dir/a.png"
check "two references"     2 -- "$fovrender" "${set[@]}" --spp 1 --reference-spp 8 --compare "$dir/ref.exr"
conv=$("$fovrender" "${set[@]}" --spp 1 --reference-spp 8 --json)
python3 - "$conv" <<'PY' || { echo "FAIL --reference-spp JSON: $conv"; failures=$((failures + 1)); }
import json, sys
j = json.loads(sys.argv[1])
assert j["reference_spp"] == 8 and j["metrics"]["flip"] > 0 and j["noise_floor"]["flip"] > 0, j
assert j["acuity"] == "csf" and j["sampler"] == "poisson", j  # the scheme of the set traced
assert j["noise_floor"]["jod"] > j["metrics"]["jod"] and j["noise_floor"]["jod_nonfoveated"] > j["metrics"]["jod_nonfoveated"], j
assert j["noise_floor"]["flip"] < j["metrics"]["flip"], "the 8-spp references must differ less than a 1-spp frame from them"
PY
check "speedup, reference" 2 -- "$fovrender" --reference "${set[@]}" --spp 1 --speedup 2 -o "$dir/a.png"
check "speedup zero"       2 -- "$fovrender" "${set[@]}" --spp 1 --speedup 0 -o "$dir/a.png"
sp=$("$fovrender" "${set[@]}" --spp 2 --speedup 3 -o "$dir/sp.png" --json)
python3 - "$sp" <<'PY' || { echo "FAIL --speedup JSON: $sp"; failures=$((failures + 1)); }
import json, sys
j = json.loads(sys.argv[1])
assert 0 < j["speedup_lo"] <= j["speedup"] <= j["speedup_hi"] and j["speedup_pairs"] == 3, j
assert j["speedup_lo"] <= j["speedup_interval"][0] <= j["speedup"] <= j["speedup_interval"][1] <= j["speedup_hi"], j
assert 0 < j["full_ms_lo"] <= j["full_ms"] <= j["full_ms_hi"] and j["frame_ms"] > 0, j
PY
# A perfect match has no PSNR: JSON writes null (never the string "inf"), and FLIP is 0.
same=$("$fovrender" --reference "${set[@]}" --spp 4 --compare "$dir/ref.exr" --json)
python3 - "$same" <<'PY' || { echo "FAIL identical frames: $same"; failures=$((failures + 1)); }
import json, sys
m = json.loads(sys.argv[1])["metrics"]
assert m["psnr"] is None and m["psnr_fovea"] is None and m["flip"] == 0 and m["foveated_flip"] == 0, m
assert all(b["psnr"] is None for b in m["bands"]), m["bands"]
# Our EXR keeps the depth: every band with pixels states its share of geometry.
assert all(0 <= b["geometry"] <= 1 for b in m["bands"] if b["pixels"]), m["bands"]
PY

json=$("$fovrender" "${set[@]}" --spp 4 --compare "$dir/ref.exr" --json)
for key in trace_ms reconstruct_ms taa_ms total_ms rays points_traced psnr ssim psnr_fovea ssim_fovea psnr_mid psnr_periphery \
    foveated_psnr flip flip_fovea foveated_flip foveated_flip_p99 foveated_flip_worst_band ppd bands; do
  grep -q "\"$key\":" <<<"$json" || { echo "FAIL --json lacks $key"; failures=$((failures + 1)); }
done
# Nested sets and refinement (docs/adaptive.md): bad values are flags (exit 2), nothing written.
"$fovgen" --width 64 --height 72 --k 6 --saturation 500 --levels 1.0,2.0,3.0 -o "$dir/nested.fovset" >/dev/null
nested=(--points "$dir/nested.fovset")
check "adaptive fixed set"  2 -- "$fovrender" "${set[@]}" --adaptive -o "$dir/ad.png"
check "threshold negative"  2 -- "$fovrender" "${nested[@]}" --adaptive --adaptive-threshold -1 -o "$dir/ad.png"
check "threshold huge"      2 -- "$fovrender" "${nested[@]}" --adaptive --adaptive-threshold 1e9 -o "$dir/ad.png"
check "threshold nan"       2 -- "$fovrender" "${nested[@]}" --adaptive --adaptive-threshold nan -o "$dir/ad.png"
check "depth negative"      2 -- "$fovrender" "${nested[@]}" --adaptive --adaptive-depth -0.5 -o "$dir/ad.png"
check "budget negative"     2 -- "$fovrender" "${nested[@]}" --adaptive --adaptive-budget -5 -o "$dir/ad.png"
check "budget text"         2 -- "$fovrender" "${nested[@]}" --adaptive --adaptive-budget lots -o "$dir/ad.png"
check "level missing"       2 -- "$fovrender" "${nested[@]}" --level 3 -o "$dir/ad.png"
check "level fixed set"     2 -- "$fovrender" "${set[@]}" --level 0 -o "$dir/ad.png"
check "level and adaptive"  2 -- "$fovrender" "${nested[@]}" --level 0 --adaptive -o "$dir/ad.png"
check "refinement view"     2 -- "$fovrender" "${nested[@]}" --debug-view refinement -o "$dir/ad.png"
check "adaptive reference"  2 -- "$fovrender" --reference --width 32 --height 32 --adaptive -o "$dir/ad.png"
[[ ! -e "$dir/ad.png" ]] && [[ ! -e "$dir/ad-refinement.png" ]] || fail "a refused --adaptive wrote a frame"
check "level"               0 -- "$fovrender" "${nested[@]}" --level 1 --spp 2 -o "$dir/l1.png"
budget_err=$("$fovrender" "${nested[@]}" --adaptive --adaptive-budget 10 --spp 2 -o "$dir/ad.png" --debug-view refinement --json 2>&1 >"$dir/ad.json")
[[ $budget_err == "fovrender: warning: --adaptive-budget 10 rays"* ]] || fail "a budget below the coarsest level was not warned: $budget_err"
python3 - "$dir/ad.json" <<'PY' || fail "--adaptive --json"
import json, sys
j = json.load(open(sys.argv[1]))
a = j["adaptive"]
assert a["budget_short"] and a["points_refined"] == 0, a
assert [l["scale"] for l in a["levels"]] == [3.0, 2.0, 1.0], a
assert j["rays"] == a["levels"][0]["rays"] > 0, j
PY
[[ -s "$dir/ad-refinement.png" ]] || fail "--debug-view refinement wrote nothing"
ls "$dir" | grep -q 'tmp-' && { echo "FAIL temporary files left: $(ls "$dir")"; failures=$((failures + 1)); }
[[ -e "$dir/no" ]] && { echo "FAIL created a directory"; failures=$((failures + 1)); }

echo "fovrender CLI: $passes passed, $failures failed"
[[ $failures -eq 0 ]]
