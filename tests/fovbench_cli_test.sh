#!/usr/bin/env bash
# fovbench end to end on a tiny screen: a smoke sweep writes every output, --resume
# skips finished rows (and redoes a lost one), bad flags exit 2 with one line.
set -uo pipefail
fovbench=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
tool=fovbench
source "$(dirname "$0")/cli_check.sh"
common=(--display 64x72 --points-dir "$dir/sets" --frames 1)

check "bad method"      2 -- "$fovbench" "${common[@]}" --methods cubic -o "$dir/x"
check "bad display"     2 -- "$fovbench" --display 64by72 -o "$dir/x"
check "bad spp"         2 -- "$fovbench" "${common[@]}" --spp 0 -o "$dir/x"
check "bad gaze"        2 -- "$fovbench" "${common[@]}" --gazes 500,10 -o "$dir/x"
check "two budgets"     2 -- "$fovbench" "${common[@]}" --budget-psnr 20 --budget-foveated 0.1 -o "$dir/x"
check "missing scene"   1 -- "$fovbench" "${common[@]}" --scene "$dir/none.gltf" -o "$dir/x"
check "bad footprint"   2 -- "$fovbench" "${common[@]}" --texture-footprint wide -o "$dir/x"
check "bad eye"         2 -- "$fovbench" "${common[@]}" --eye 1,2 -o "$dir/x"
echo "not a glTF file" > "$dir/broken.gltf"
check "broken 2nd scene" 1 -- "$fovbench" "${common[@]}" --scene builtin --scene "$dir/broken.gltf" --spp 1 -o "$dir/broken"
[[ -e "$dir/broken" ]] && fail "a sweep with a broken scene wrote $(ls -R "$dir/broken" | tr '\n' ' ')"

sweep=("$fovbench" "${common[@]}" --scene builtin --scales 1.0,2.0 --methods nn,shepard --k 4 --spp 1,2
       --gazes "centre;20,30" --temporal-frames 2 --budget-psnr 10 -o "$dir/out")
check "smoke sweep"     0 -- "${sweep[@]}"
for f in results.csv pareto.png error_by_eccentricity.png speedup_vs_scale.png report.md; do
  [[ -s "$dir/out/$f" ]] || fail "no $f"
done
python3 - "$dir/out/results.csv" <<'PY' || fail "results.csv contents"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 2 * 2 * 2 * 2, len(rows)  # scales x gazes x spp x (nn, shepard k=4)
need = "scene gaze scale method k spp points_traced rays frame_ms reference_ms speedup psnr ssim psnr_fovea foveated_error".split()
for r in rows:
    for c in need:
        assert r[c] != "", (c, r)
    assert float(r["frame_ms"]) > 0 and float(r["speedup"]) > 0
    assert abs(float(r["speedup"]) - float(r["reference_ms"]) / float(r["frame_ms"])) < 1e-3 * float(r["speedup"])
    assert 0 <= float(r["foveated_error"]) < 1 and float(r["flicker"]) >= 0
assert {r["gaze"] for r in rows} == {"centre", "20_30"}
assert {r["texture_footprint"] for r in rows} == {"disc"}
PY
grep -q "Fastest within the budget" "$dir/out/report.md" || fail "report.md names no fastest configuration"

check "exists without --resume" 1 -- "${sweep[@]}"
out=$("${sweep[@]}" --resume 2>&1)
[[ "$out" == *"16 already in"*"0 to measure"* ]] || fail "resume did not skip all: $out"
head -n -1 "$dir/out/results.csv" > "$dir/cut.csv" && mv "$dir/cut.csv" "$dir/out/results.csv"
out=$("${sweep[@]}" --resume 2>&1)
[[ "$out" == *"15 already in"*"1 to measure"* ]] || fail "resume did not redo the lost row: $out"
[[ $(($(wc -l < "$dir/out/results.csv") - 1)) -eq 16 ]] || fail "resumed CSV should hold 16 rows"
check "resume, other footprint" 1 -- "${sweep[@]}" --resume --texture-footprint pixel
# The pixel footprint reads sharper textures: the same configurations, other colours.
"$fovbench" "${common[@]}" --scene builtin --scales 2.0 --methods nn --spp 1 --texture-footprint pixel \
  -o "$dir/pixel" >/dev/null 2>&1 || fail "pixel-footprint sweep"
python3 - "$dir/out/results.csv" "$dir/pixel/results.csv" <<'PY' || fail "pixel footprint rows"
import csv, sys
disc = {(r["gaze"], r["scale"], r["method"], r["spp"]): r for r in csv.DictReader(open(sys.argv[1]))}
pixel = list(csv.DictReader(open(sys.argv[2])))
assert len(pixel) == 1 and pixel[0]["texture_footprint"] == "pixel", pixel
d = disc[("centre", "2.00", "nn", "1")]
assert d["points_traced"] == pixel[0]["points_traced"]
assert d["psnr"] != pixel[0]["psnr"], "the footprint changed no colour"
PY

echo "$passes passed, $failures failed"
[[ $failures -eq 0 ]]
