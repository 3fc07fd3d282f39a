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
check "bad fovea"       2 -- "$fovbench" "${common[@]}" --fovea hex -o "$dir/x"
check "bad acuity"      2 -- "$fovbench" "${common[@]}" --acuity wang_csf -o "$dir/x"
check "bad sampler"     2 -- "$fovbench" "${common[@]}" --sampler hex -o "$dir/x"
check "bad grid spacing" 2 -- "$fovbench" "${common[@]}" --fovea grid --grid-spacing nan -o "$dir/x"
check "spacing, darts"  2 -- "$fovbench" "${common[@]}" --grid-spacing 1.1 -o "$dir/x"
check "bad eye"         2 -- "$fovbench" "${common[@]}" --eye 1,2 -o "$dir/x"
check "bad baseline"    2 -- "$fovbench" "${common[@]}" --baselines lowres -o "$dir/x"
check "bad fraction"    2 -- "$fovbench" "${common[@]}" --baselines uniform --uniform-fractions 0.3 -o "$dir/x"
check "weak reference"  2 -- "$fovbench" "${common[@]}" --spp 4 --reference-spp 4 -o "$dir/x"
check "bad temporal fps" 2 -- "$fovbench" "${common[@]}" --temporal-frames 2 --temporal-fps 4 -o "$dir/x"
check "bad spread"      2 -- "$fovbench" "${common[@]}" --spread-limit 0 -o "$dir/x"
check "budget nan"      2 -- "$fovbench" "${common[@]}" --budget-psnr nan -o "$dir/x"
check "foveated budget inf" 2 -- "$fovbench" "${common[@]}" --budget-foveated inf -o "$dir/x"
check "taa one frame"   2 -- "$fovbench" "${common[@]}" --taa-frames 1 -o "$dir/x"
check "taa too many"    2 -- "$fovbench" "${common[@]}" --taa-frames 4,257 -o "$dir/x"
check "taa not a count" 2 -- "$fovbench" "${common[@]}" --taa-frames many -o "$dir/x"
check "pattern, no taa" 2 -- "$fovbench" "${common[@]}" --pattern mirror -o "$dir/x"
check "bad pattern"     2 -- "$fovbench" "${common[@]}" --taa-frames 4 --pattern swirl -o "$dir/x"
check "taa yardstick"   2 -- "$fovbench" "${common[@]}" --taa-frames 4 --yardstick -o "$dir/x"
echo "a file" > "$dir/plain"
check "-o a file"       2 -- "$fovbench" "${common[@]}" -o "$dir/plain"
[[ -e "$dir/x" ]] && fail "a refused sweep wrote $dir/x"
echo "not a glTF file" > "$dir/broken.gltf"
check "broken 2nd scene" 1 -- "$fovbench" "${common[@]}" --scene builtin --scene "$dir/broken.gltf" --spp 1 -o "$dir/broken"
[[ -e "$dir/broken" ]] && fail "a sweep with a broken scene wrote $(ls -R "$dir/broken" | tr '\n' ' ')"

base=("$fovbench" "${common[@]}" --scene builtin --scales 1.0,2.0 --methods nn,shepard --k 4 --spp 1,2
      --gazes "centre;20,30" --temporal-frames 2 --budget-psnr 10 --baselines full,uniform --uniform-fractions 0.25
      --ray-floors 1 -o "$dir/out")
sweep=("${base[@]}" --reference-spp 16)
check "smoke sweep"     0 -- "${sweep[@]}"
for f in results.csv report.md {pareto_jod,pareto,pareto_flip,error_by_eccentricity,speedup_vs_scale}.{png,svg}; do
  [[ -s "$dir/out/$f" ]] || fail "no $f"
done
python3 - "$dir/out/results.csv" <<'PY' || fail "results.csv contents"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
kinds = [r["kind"] for r in rows]
# foveated: scales x gazes x spp x (nn, shepard k=4); uniform: 1 fraction x gazes x spp x 2; full: gazes x spp;
# falloff: scales x gazes x the spp above floor 1 (2)
assert kinds.count("foveated") == 16 and kinds.count("uniform") == 8 and kinds.count("full") == 4, kinds
assert kinds.count("falloff") == 4, kinds
need = ("scene gaze kind method spp rays frame_ms frame_ms_lo frame_ms_hi full_ms speedup speedup_lo speedup_hi psnr ssim "
        "psnr_fovea foveated_error flip flip_fovea foveated_flip foveated_flip_p99 foveated_flip_worst_band reference_spp "
        "noise_floor_psnr noise_floor_flip noise_floor_foveated_flip geometry_fovea jod jod_nonfoveated noise_floor_jod "
        "noise_floor_jod_nonfoveated").split()
for r in rows:
    for c in need:
        assert r[c] != "", (c, r)
    lo, mid, hi = float(r["frame_ms_lo"]), float(r["frame_ms"]), float(r["frame_ms_hi"])
    assert 0 < lo <= mid <= hi, r
    assert float(r["trace_cpu_ms"]) >= 0 and float(r["full_cpu_ms"]) >= 0, r
    if r["kind"] != "full":
        samples = [float(x) for x in r["speedup_samples"].split(";")]
        assert len(samples) == 1 and samples[0] > 0 and r["ladder_samples"] == "", r  # --frames 1
    else:
        assert r["speedup_samples"] == "", r
        ladder = [float(x) for x in r["ladder_samples"].split(";")]
        assert len(ladder) == 1 and (r["spp"] != "1" or ladder == [1.0]), r
    assert float(r["speedup_lo"]) <= float(r["speedup"]) <= float(r["speedup_hi"]), r
    assert 0 <= float(r["foveated_error"]) < 1 and 0 <= float(r["flip"]) <= 1 and 0 <= float(r["foveated_flip"]) <= 1
    assert r["reference_spp"] == "16"
    assert 0 < float(r["noise_floor_flip"]) < float(r["flip"]), "the reference must be better than what it measures"
    assert float(r["jod"]) <= 10 and float(r["jod_nonfoveated"]) <= 10 and float(r["noise_floor_jod"]) > float(r["jod"]), r
    if r["kind"] == "full":
        assert r["method"] == "full" and float(r["speedup"]) == 1 and r["scale"] == "" and r["pixel_fraction"] == "1.0000", r
    elif r["kind"] == "falloff":
        assert r["method"] == "falloff" and r["ray_floor"] == "1" and r["spp"] == "2" and r["flicker"] == "", r
    else:
        assert float(r["flicker"]) >= 0
        v = {c: float(r[c]) for c in ("video_jod", "video_jod_taa", "video_jod_full", "noise_floor_video_jod",
                                      "video_jod_nonfoveated", "noise_floor_video_jod_nonfoveated")}
        assert max(v.values()) <= 10 and v["noise_floor_video_jod"] > v["video_jod"], v
    if r["kind"] == "uniform":
        assert r["pixel_fraction"] == "0.2500" and r["scale"] == "", r
# On this tiny screen (N v = 64) the model asks for every pixel's full density everywhere: a
# falloff frame casts spp rays in every pixel, the full-resolution frame's, at any scale.
for r in rows:
    if r["kind"] == "falloff":
        full = [f for f in rows if f["kind"] == "full" and f["spp"] == r["spp"] and f["gaze"] == r["gaze"]][0]
        assert r["rays"] == full["rays"] and r["flip"] == full["flip"] and r["jod"] == full["jod"], (r, full)
# One full frame at 2 spp against the 16-spp reference errs less than at 1 spp.
full = {(r["gaze"], r["spp"]): float(r["flip"]) for r in rows if r["kind"] == "full"}
assert full[("centre", "2")] < full[("centre", "1")], full
assert {r["gaze"] for r in rows} == {"centre", "20_30"}
assert {r["texture_footprint"] for r in rows} == {"disc"}
assert {r["fovea"] for r in rows} == {"darts"}
assert {r["display"] for r in rows} == {"64x72-v1"} and {r["ppd"] for r in rows} == {"%.6g" % (64 * math.pi / 180)}, rows[0]
PY
# --viewing-distance: another display, so another set (named by display_name) and rows that
# say so; the first sweep's results.csv does not take them.
check "bad v"           2 -- "$fovbench" "${common[@]}" --viewing-distance 0 -o "$dir/x"
check "ray floor zero"  2 -- "$fovbench" "${common[@]}" --ray-floors 0 -o "$dir/x"
check "ray floor high"  2 -- "$fovbench" "${common[@]}" --spp 1,4 --ray-floors 4 -o "$dir/x"
check "point floor zero" 2 -- "$fovbench" "${common[@]}" --point-ray-floors 0 -o "$dir/x"
check "point floor high" 2 -- "$fovbench" "${common[@]}" --spp 1,4 --point-ray-floors 4 -o "$dir/x"
check "point floor, no sets" 2 -- "$fovbench" "${common[@]}" --spp 4 --no-sparse --ray-floors 1 --point-ray-floors 1 -o "$dir/x"
check "bad ppd display" 2 -- "$fovbench" --display 64x72@0ppd --points-dir "$dir/sets" -o "$dir/x"
# Rays per point falling with eccentricity (--point-ray-floors): seen from 10 screen widths at
# scale 4 the model's spacing grows across the screen, so the floor rows trace the same points
# with fewer rays.
check "point floors"    0 -- "$fovbench" --display 128x96@10 --points-dir "$dir/sets" --frames 1 --scene builtin \
  --scales 4.0 --methods nn,shepard --k 4 --spp 4 --point-ray-floors 1,2 --baselines full --reference-spp 8 --no-flip -o "$dir/pf"
python3 - "$dir/pf/results.csv" <<'PY' || fail "--point-ray-floors rows"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["kind"] == "foveated"]
by = {(r["method"], r["ray_floor"]): r for r in rows}
assert sorted(by) == sorted((m, f) for m in ("nn", "shepard") for f in ("", "1", "2")), sorted(by)
for m in ("nn", "shepard"):
    flat, two, one = by[(m, "")], by[(m, "2")], by[(m, "1")]
    assert flat["points_traced"] == two["points_traced"] == one["points_traced"], (flat, one)
    pts = int(flat["points_traced"])
    assert int(flat["rays"]) == 4 * pts and pts <= int(one["rays"]) < int(two["rays"]) < int(flat["rays"]), (flat, two, one)
    assert int(one["rays"]) >= pts and int(two["rays"]) >= 2 * pts
PY
# Adaptive rows (issue 26): a nested set refined per frame at each threshold beside the fixed
# sets, in results.csv as density adaptive with its threshold, levels and rays per level.
check "thresholds, no levels" 2 -- "$fovbench" "${common[@]}" --adaptive-thresholds 1 -o "$dir/x"
check "levels, no thresholds" 2 -- "$fovbench" "${common[@]}" --levels 1.0,2.0 -o "$dir/x"
check "levels decreasing" 2 -- "$fovbench" "${common[@]}" --levels 2.0,1.0 --adaptive-thresholds 1 -o "$dir/x"
check "threshold negative" 2 -- "$fovbench" "${common[@]}" --levels 1.0,2.0 --adaptive-thresholds -1 -o "$dir/x"
check "threshold nan"   2 -- "$fovbench" "${common[@]}" --levels 1.0,2.0 --adaptive-thresholds nan -o "$dir/x"
check "levels, grid"    2 -- "$fovbench" "${common[@]}" --levels 1.0,2.0 --adaptive-thresholds 1 --fovea grid -o "$dir/x"
[[ -e "$dir/x" ]] && fail "a refused adaptive sweep wrote $dir/x"
check "adaptive rows"   0 -- "$fovbench" --display 128x96@10 --points-dir "$dir/sets" --frames 1 --scene builtin \
  --scales 2.0,4.0 --levels 2.0,4.0 --adaptive-thresholds 0,1000 --methods nn,shepard --k 4 --spp 2 --baselines full \
  --reference-spp 8 --no-flip -o "$dir/adaptive"
[[ -s "$dir/sets/128x96-v10-n2.00-4.00.fovset" ]] || fail "no nested set in --points-dir: $(ls "$dir/sets")"
python3 - "$dir/adaptive/results.csv" "$dir/adaptive/report.md" <<'PY' || fail "adaptive rows"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["kind"] == "foveated"]
fixed = {(r["method"], r["scale"]): r for r in rows if r["density"] == "fixed"}
adaptive = {(r["method"], r["adaptive_threshold"]): r for r in rows if r["density"] == "adaptive"}
assert sorted(fixed) == sorted((m, s) for m in ("nn", "shepard") for s in ("2.00", "4.00")), sorted(fixed)
assert sorted(adaptive) == sorted((m, t) for m in ("nn", "shepard") for t in ("0", "1000")), sorted(adaptive)
for m in ("nn", "shepard"):
    for t in ("0", "1000"):
        r = adaptive[(m, t)]
        per = [int(v) for v in r["level_rays"].split(";")]
        assert r["levels"] == "2.00;4.00" and r["scale"] == "" and len(per) == 2 and sum(per) == int(r["rays"]), r
        assert float(r["jod"]) <= 10 and float(r["speedup"]) > 0, r
    none, every = adaptive[(m, "1000")], adaptive[(m, "0")]
    # Nothing refined at 1000: the coarsest level's rays, as its fixed set's at k = 4 (at k = 1
    # the fixed path traces points no pixel's nearest neighbour is, the adaptive one not);
    # refined at 0.
    coarsest = fixed[(m, "4.00")]
    assert none["level_rays"].split(";")[1] == "0", none
    assert none["rays"] == coarsest["rays"] if m == "shepard" else int(none["rays"]) <= int(coarsest["rays"]), (none, coarsest)
    assert int(every["level_rays"].split(";")[1]) > 0 and int(every["rays"]) > int(none["rays"]), every
report = open(sys.argv[2]).read()
assert "| adaptive |" in report and "adaptive T0 " in report, "the report names no adaptive scheme"
PY
# Reuse rows (issue 28): a fixed set's frames also along the temporal path with --reuse temporal.
check "reuse eyes"      2 -- "$fovbench" "${common[@]}" --reuse eyes --temporal-frames 2 -o "$dir/x"
check "reuse, no path"  2 -- "$fovbench" "${common[@]}" --reuse temporal -o "$dir/x"
check "reuse knob alone" 2 -- "$fovbench" "${common[@]}" --reuse-fovea 0 --temporal-frames 2 -o "$dir/x"
check "reuse threshold 2" 2 -- "$fovbench" "${common[@]}" --reuse temporal --reuse-threshold 2 --temporal-frames 2 -o "$dir/x"
check "bad reuse edges" 2 -- "$fovbench" "${common[@]}" --reuse temporal --reuse-edges soft --temporal-frames 2 -o "$dir/x"
check "reuse, no sparse" 2 -- "$fovbench" "${common[@]}" --reuse temporal --temporal-frames 2 --no-sparse --ray-floors 1 \
  --spp 2 -o "$dir/x"
check "reuse yardstick" 2 -- "$fovbench" "${common[@]}" --reuse temporal --temporal-frames 2 --yardstick -o "$dir/x"
[[ -e "$dir/x" ]] && fail "a refused reuse sweep wrote $dir/x"
reuse=("$fovbench" --display 128x96@10 --points-dir "$dir/sets" --frames 1 --scene builtin --scales 2.0 --methods nn,shepard
       --k 4 --spp 2 --baselines full --reference-spp 8 --no-flip --temporal-frames 3 --reuse temporal --reuse-fovea 0
       --reuse-edges silhouettes -o "$dir/reuse")
check "reuse rows"      0 -- "${reuse[@]}" --reuse-threshold 0
check "reuse, other settings" 0 -- "${reuse[@]}" --reuse-threshold 0.5 --resume
out=$("${reuse[@]}" --reuse-threshold 0.5 --resume 2>&1)
[[ "$out" == *"5 configurations, 5 already in"*"0 to measure"* ]] || fail "a resumed reuse sweep measured again: $out"
check "reuse summary"   0 -- "$fovbench" summary "$dir/reuse" -o "$dir/reuse-summary"
python3 - "$dir/reuse/results.csv" "$dir/reuse/report.md" <<'PY' || fail "reuse rows"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["kind"] == "foveated"]
fixed = {r["method"]: r for r in rows if r["reuse"] == ""}
reuse = {(r["method"], r["reuse_settings"].split()[1]): r for r in rows if r["reuse"] == "temporal"}
assert sorted(fixed) == ["nn", "shepard"], sorted(fixed)
assert sorted(reuse) == sorted((m, t) for m in ("nn", "shepard") for t in ("threshold=0", "threshold=0.5")), sorted(reuse)
for (m, t), r in reuse.items():
    f = fixed[m]
    assert r["reuse_settings"].startswith("fovea=0 ") and "edges=silhouettes" in r["reuse_settings"], r["reuse_settings"]
    # The fully traced sequence along the path is the fixed row's own temporal sequence.
    assert r["reuse_video_jod_traced"] == f["video_jod"] and r["reuse_flicker_traced"] == f["flicker"], (r, f)
    assert r["psnr"] == "" and r["jod"] == "" and r["flicker"] != "" and float(r["video_jod"]) <= 10, r
    assert float(r["speedup"]) > 0 and float(r["reuse_trace_ratio_lo"]) <= float(r["reuse_trace_ratio"]), r
    assert 0 <= float(r["reuse_kept"]) <= 1 and int(r["rays_cast"]) >= int(r["rays"]) > 0, r
# Threshold 0 keeps what any confidence keeps: more than 0.5 does, and fewer rays in all.
for m in ("nn", "shepard"):
    loose, strict = reuse[(m, "threshold=0")], reuse[(m, "threshold=0.5")]
    assert float(loose["reuse_kept"]) > float(strict["reuse_kept"]) > 0, (loose, strict)
    assert float(loose["reuse_rays_cast_ratio"]) < min(1.0, float(strict["reuse_rays_cast_ratio"])), (loose, strict)
report = open(sys.argv[2]).read()
assert "## Temporal reuse along the temporal path" in report, "no reuse section"
assert report.count("| builtin (direct) | centre |") == 4, report
PY
check "farther eye"     0 -- "$fovbench" "${common[@]}" --viewing-distance 2 --scene builtin --scales 1.0 --methods nn --spp 1 \
  --baselines full --reference-spp 4 -o "$dir/far"
[[ -s "$dir/sets/64x72-v2-s1.00.fovset" ]] || fail "v = 2 did not write 64x72-v2-s1.00.fovset: $(ls "$dir/sets")"
grep -q ",64x72-v2,$(python3 -c 'import math; print("%.6g" % (128 * math.pi / 180))')," "$dir/far/results.csv" \
  || fail "v = 2 rows do not name their display and ppd"
check "bad neighbours"  2 -- "$fovbench" "${common[@]}" --neighbours grid -o "$dir/x"
# The same sweep reading k-NN cells built from the same set file: the same errors, rows that say so.
check "cells sweep"     0 -- "$fovbench" "${common[@]}" --viewing-distance 2 --scene builtin --scales 1.0 --methods nn,shepard \
  --spp 1 --baselines full --reference-spp 4 --neighbours cells -o "$dir/far-cells"
python3 - "$dir/far/results.csv" "$dir/far-cells/results.csv" <<'PY' || fail "a cells sweep's rows differ from the table's"
import csv, sys
table, cells = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
sparse = lambda rows: {(r["method"], r["spp"]): r for r in rows if r["kind"] == "foveated"}
t, c = sparse(table), sparse(cells)
assert ("nn", "1") in c and ("shepard", "1") in c, c.keys()
for key, row in c.items():
    assert row["neighbours"] == "cells" and t.get(key, {}).get("neighbours", "table") == "table", (key, row["neighbours"])
    if key in t:
        assert row["psnr"] == t[key]["psnr"] and row["flip"] == t[key]["flip"] and row["jod"] == t[key]["jod"], key
PY
check "resume, other display" 1 -- "$fovbench" "${common[@]}" --viewing-distance 2 --scene builtin --scales 1.0 --methods nn \
  --spp 1 --baselines full --reference-spp 16 --resume -o "$dir/out"
[[ -e "$dir/x" ]] && fail "a refused sweep wrote $dir/x"
# A grid fovea: on this tiny screen (N v = 64) the model asks for more than a pixel's density
# everywhere, so the whole set is a pixel grid and every foveated nn frame is the full frame.
check "grid sweep"      0 -- "$fovbench" "${common[@]}" --scene builtin --scales 1.0 --methods nn --spp 1,2 \
  --baselines full --reference-spp 8 --fovea grid -o "$dir/grid"
[[ -s "$dir/sets/64x72-v1-s1.00-grid.fovset" ]] || fail "the grid sweep did not write its -grid set"
python3 - "$dir/grid/results.csv" <<'PY' || fail "grid results.csv"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert {r["fovea"] for r in rows} == {"grid"}, rows
for spp in ("1", "2"):
    fov = [r for r in rows if r["kind"] == "foveated" and r["spp"] == spp]
    full = [r for r in rows if r["kind"] == "full" and r["spp"] == spp]
    assert len(fov) == 1 and len(full) == 1, rows
    assert fov[0]["flip"] == full[0]["flip"] and fov[0]["psnr"] == full[0]["psnr"], (fov[0]["flip"], full[0]["flip"])
PY
grep -q "Equal-error speedup over the best baseline" "$dir/out/report.md" || fail "report.md has no equal-error speedup"
grep -q "^## Verdict (JOD" "$dir/out/report.md" || fail "report.md opens with no verdict"
grep -Eq "^\*\*builtin\*\*: (Foveation|Inconclusive|No verdict)" "$dir/out/report.md" || fail "report.md has no verdict sentence"
grep -Eq "^- (At [0-9.]+ JOD|No foveated configuration reaches)" "$dir/out/report.md" || fail "report.md has no verdict line"
grep -q "noise floor" "$dir/out/report.md" || fail "report.md states no noise floor"
grep -q "Timing noise" "$dir/out/report.md" || fail "report.md states no timing noise"
grep -q "Fastest within the budget" "$dir/out/report.md" || fail "report.md names no fastest configuration"

# Shards: two slices of a small sweep (one by --shard, one by Slurm's variables) sharing one
# reference cache, merged, hold the one run's rows with the same errors; every row also in
# steady state after 3 frames of TAA (mirrored patterns), which must be as deterministic.
small=("$fovbench" "${common[@]}" --scene builtin --scales 1.0 --methods nn,shepard --k 4 --spp 1,2 --baselines full
       --reference-spp 16 --ray-floors 1 --taa-frames 3 --pattern mirror)
check "bad shard"       2 -- "${small[@]}" --shard 2/2 -o "$dir/x"
check "bad shard text"  2 -- "${small[@]}" --shard 1of2 -o "$dir/x"
check "bad slurm id"    2 -- env SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_ID=x "${small[@]}" -o "$dir/x"
check "slurm id beyond" 2 -- env SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_ID=5 SLURM_ARRAY_TASK_MIN=1 "${small[@]}" -o "$dir/x"
[[ -e "$dir/x" ]] && fail "a refused shard wrote $dir/x"
check "one run"         0 -- "${small[@]}" -o "$dir/whole"
check "shard 0 of 2"    0 -- "${small[@]}" --shard 0/2 -o "$dir/sharded"
check "shard 1 of 2"    0 -- env SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_ID=4 SLURM_ARRAY_TASK_MIN=3 "${small[@]}" -o "$dir/sharded"
check "merge"           0 -- "$fovbench" merge "$dir/sharded/shard-0-of-2" "$dir/sharded/shard-1-of-2/results.csv" -o "$dir/merged"
[[ -s "$dir/merged/report.md" && -s "$dir/merged/pareto_jod.png" ]] || fail "merge wrote no report or figures"
grep -q '^\*\*builtin, TAA steady state (3 frames, mirror)\*\*: ' "$dir/merged/report.md" || fail "the report has no steady-state verdict"
grep -q '^## builtin, TAA steady state (3 frames, mirror)$' "$dir/merged/report.md" || fail "the report has no steady-state section"
python3 - "$dir/whole/results.csv" "$dir/merged/results.csv" "$dir/sharded" <<'PY' || fail "merged shards differ from one run"
import csv, sys, os
def rows(p):
    return {"|".join(r[c] for c in ("scene", "gaze", "kind", "scale", "method", "k", "ray_floor", "spp", "taa_frames",
                                    "taa_pattern")): r
            for r in csv.DictReader(open(p))}
whole, merged = rows(sys.argv[1]), rows(sys.argv[2])
assert set(whole) == set(merged) and len(whole) == 14, (sorted(whole), sorted(merged))
shards = [len(list(csv.DictReader(open(os.path.join(sys.argv[3], d, "results.csv"))))) for d in ("shard-0-of-2", "shard-1-of-2")]
assert shards == [7, 7], shards
# Each configuration once as a single frame and once in steady state; TAA costs time on
# both sides of every pair, and on the full grid its blend of three patterns errs less.
steady = {k: r for k, r in whole.items() if r["taa_frames"]}
assert len(steady) == 7 and all(r["taa_frames"] == "3" and r["taa_pattern"] == "mirror" for r in steady.values()), steady
for k, r in steady.items():
    single = whole[k.replace("|3|mirror", "||")]
    if r["kind"] != "falloff":  # timed in the same repetitions as its single frame
        assert float(r["frame_ms"]) > float(single["frame_ms"]) and float(r["full_ms"]) > float(single["full_ms"]), (k, r["frame_ms"])
    if r["kind"] == "full":
        assert float(r["psnr"]) > float(single["psnr"]) + 0.5, (k, r["psnr"], single["psnr"])
        assert float(r["jod"]) > float(single["jod"]), (k, r["jod"], single["jod"])
for key, r in whole.items():
    for c in ("rays", "points_traced", "psnr", "ssim", "flip", "foveated_flip", "foveated_error", "jod", "jod_nonfoveated",
              "noise_floor_flip", "noise_floor_jod", "error_profile"):
        assert r[c] == merged[key][c], (key, c, r[c], merged[key][c])
PY
check "merge a shard twice" 1 -- "$fovbench" merge "$dir/sharded/shard-0-of-2" "$dir/sharded/shard-0-of-2" -o "$dir/twice"
check "merge other display" 1 -- "$fovbench" merge "$dir/whole" "$dir/far" -o "$dir/mixed"
check "merge onto results" 2 -- "$fovbench" merge "$dir/whole" -o "$dir/merged"
check "merge nothing"   2 -- "$fovbench" merge -o "$dir/none"

# fovbench summary: one answer per display and scheme from runs on two displays (one with a
# steady state), the same answers the run's own report gives; bad inputs refused.
grep -q '^## Each scheme at the cheapest full frame reaching 9.5 JOD$' "$dir/whole/report.md" || fail "report.md answers no scheme"
check "summary"         0 -- "$fovbench" summary "$dir/whole" "$dir/far" -o "$dir/summary"
for f in summary.md summary.csv speedup-vs-ppd.png speedup-vs-ppd.svg jod-vs-ppd.png jod-vs-ppd.svg; do
  [[ -s "$dir/summary/$f" ]] || fail "summary wrote no $f"
done
grep -q '^\*\*builtin, TAA steady state (3 frames, mirror)\*\*$' "$dir/summary/summary.md" || fail "the summary has no steady state"
python3 - "$dir/summary/summary.csv" "$dir/whole/report.md" <<'PY' || fail "summary.csv does not hold the run's answers"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert {r["display"] for r in rows} == {"64x72-v1", "64x72-v2"}, {r["display"] for r in rows}
assert {r["taa_frames"] for r in rows} == {"", "3"}
assert {r["scheme"] for r in rows} <= {"sparse", "hybrid", "falloff", "lower-resolution"}
report = open(sys.argv[2]).read()
for r in rows:
    spp, jod = int(r["yardstick_spp"]), float(r["yardstick_jod"])
    assert spp in (1, 2) and 0 <= jod <= 10, r
    if r["reached"] == "1":
        assert float(r["best_jod"]) >= jod and float(r["speedup_lo"]) <= float(r["speedup"]) <= float(r["speedup_hi"]), r
        if r["display"] == "64x72-v1":  # the run's own report prices it alike
            assert f'**{float(r["speedup"]):.2f}x** ({float(r["speedup_lo"]):.2f}-{float(r["speedup_hi"]):.2f}' in report, r
    else:
        assert float(r["best_jod"]) < jod and r["speedup"] == "", r
PY
check "summary again"   2 -- "$fovbench" summary "$dir/whole" -o "$dir/summary"
check "summary nothing" 2 -- "$fovbench" summary -o "$dir/summary-x"
check "summary no -o"   2 -- "$fovbench" summary "$dir/whole"
check "summary missing" 2 -- "$fovbench" summary "$dir/none" -o "$dir/summary-x"
check "summary empty dir" 2 -- "$fovbench" summary "$dir/summary" -o "$dir/summary-x"
check "summary target"  2 -- "$fovbench" summary "$dir/whole" --target-jod 11 -o "$dir/summary-x"
check "summary target text" 2 -- "$fovbench" summary "$dir/whole" --target-jod high -o "$dir/summary-x"
echo "scene,gaze" > "$dir/foreign.csv"
check "summary foreign csv" 1 -- "$fovbench" summary "$dir/foreign.csv" -o "$dir/summary-x"
[[ -e "$dir/summary-x" ]] && fail "a refused summary wrote $dir/summary-x"

# fovbench compare: two images, every metric.
refs=("$dir"/out/references/*.exr)
check "compare"           0 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --flip-map "$dir/map.png"
[[ -s "$dir/map.png" ]] || fail "compare wrote no FLIP map"
check "compare bad size"  2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --display fove
check "compare bad disp"  2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --display 64by72
check "compare bad v"     2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --viewing-distance nan
check "compare bad gaze"  2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --gaze 1000,1
check "compare missing"   1 -- "$fovbench" compare "${refs[0]}" "$dir/none.exr"
check "compare one"       2 -- "$fovbench" compare "${refs[0]}"
same=$("$fovbench" compare "${refs[0]}" "${refs[0]}" --display 64x72 --viewing-distance 2 --json)
python3 - "$same" <<'PY' || fail "compare of identical images: $same"
import json, sys
j = json.loads(sys.argv[1])
assert j["psnr"] is None and j["flip"] == 0 and j["foveated_flip"] == 0 and j["display"]["viewing_distance"] == 2, j
assert j["jod"] == 10 and j["jod_nonfoveated"] == 10 and j["photometry"]["peak_luminance"] == 100, j
PY
check "compare bad peak"  2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --peak-luminance 0
check "compare bad contrast" 2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --contrast nan
check "compare bad ambient" 2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --ambient -1
check "frames, no fps"   2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --frames 2
check "fps out of range"  2 -- "$fovbench" compare "${refs[0]}" "${refs[1]}" --fps 5 --frames 2
check "sweep bad peak"    2 -- "$fovbench" "${common[@]}" --peak-luminance inf -o "$dir/x"
# Less light, less sensitivity: the same pair scores higher on a dimmer display (seen from
# 20 widths: 22 pixels per degree, the FOVE's).
far=(--viewing-distance 20 --no-flip --json)
bright=$("$fovbench" compare "${refs[0]}" "${refs[1]}" "${far[@]}")
dim=$("$fovbench" compare "${refs[0]}" "${refs[1]}" "${far[@]}" --peak-luminance 1)
nojod=$("$fovbench" compare "${refs[0]}" "${refs[1]}" "${far[@]}" --no-jod)
python3 - "$bright" "$dim" "$nojod" <<'PY' || fail "compare's JOD against the display's light"
import json, sys
b, d, n = (json.loads(a) for a in sys.argv[1:])
assert b["jod"] < d["jod"] <= 10 and b["jod_nonfoveated"] < d["jod_nonfoveated"], (b["jod"], d["jod"])
assert "jod" not in n and "photometry" not in n, n
PY
# A row of the validation set, from the command line (../shared absent: skipped).
val=$(dirname "$0")/../../shared/metric-validation
if [[ -f "$val/jod-reference.json" ]]; then
  row=$("$fovbench" compare "$val/images/forest--blur-3.png" "$val/images/forest.png" --display 512x512 \
        --viewing-distance 2.5 --gaze 256,256 --json)
  python3 - "$row" "$val/jod-reference.json" <<'PY' || fail "compare does not reproduce a validation row"
import json, sys
j = json.loads(sys.argv[1])
ref = [r for r in json.load(open(sys.argv[2]))["rows"] if r["test"] == "images/forest--blur-3.png"][0]
assert abs(j["jod"] - ref["jod_foveated_centre"]) < 0.1 and abs(j["jod_nonfoveated"] - ref["jod_nonfoveated"]) < 0.1, (j, ref)
PY
  check "validate-jod"    0 -- "$fovbench" validate-jod "$val"
  # A video row: new noise every frame against a still reference.
  video=$("$fovbench" compare "$val/video/flicker-0.03-%02d.png" "$val/video/reference.png" --fps 60 --frames 12 \
          --display 256x256 --viewing-distance 5 --gaze 128,128 --json)
  python3 - "$video" "$val/jod-reference.json" <<'PY' || fail "compare --fps does not reproduce the flicker row"
import json, sys
j = json.loads(sys.argv[1])
rows = [r for r in json.load(open(sys.argv[2]))["rows"] if r["test"].startswith("video/flicker")]
ref = {k: v for r in rows for k, v in r.items() if k.startswith("jod_")}
assert j["frames"] == 12 and abs(j["jod"] - ref["jod_foveated_centre"]) < 0.1, (j, ref)
assert abs(j["jod_nonfoveated"] - ref["jod_nonfoveated"]) < 0.1, (j, ref)
PY
  check "video, no frames" 2 -- "$fovbench" compare "$val/video/flicker-0.03-%02d.png" "$val/video/reference.png" --fps 60
  check "video, no number" 2 -- "$fovbench" compare "$val/video/reference.png" "$val/video/reference.png" --fps 60 --frames 2
  check "video, %s"       2 -- "$fovbench" compare "$val/video/flicker-%s.png" "$val/video/reference.png" --fps 60 --frames 2
  check "video, missing"  1 -- "$fovbench" compare "$val/video/flicker-0.03-%02d.png" "$val/video/reference.png" --fps 60 --frames 13
else
  echo "skip: ../shared/metric-validation is absent"
fi
check "validate-jod none" 1 -- "$fovbench" validate-jod "$dir"

# The yardstick: JOD through TAA against full resolution with the same rays, still and moving.
check "yardstick, no path" 2 -- "$fovbench" "${common[@]}" --yardstick -o "$dir/y"
check "yardstick, no jod" 2 -- "$fovbench" "${common[@]}" --yardstick --temporal-frames 2 --no-jod -o "$dir/y"
check "yardstick"       0 -- "$fovbench" "${common[@]}" --yardstick --scales 1.0,2.0 --methods nn,shepard --spp 2 \
  --temporal-frames 2 -o "$dir/y"
for f in yardstick.csv yardstick.md yardstick_jod.png yardstick_jod.svg; do [[ -s "$dir/y/$f" ]] || fail "yardstick wrote no $f"; done
python3 - "$dir/y/yardstick.csv" <<'PY' || fail "yardstick.csv"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 2 * 2 * 2, rows  # scales x methods x paths
assert {r["path"] for r in rows} == {"still", "moving"} and {r["method"] for r in rows} == {"nn", "shepard"}
for r in rows:
    assert float(r["jod_taa"]) <= 10 and r["frames"] == "2" and r["spp"] == "2", r
    assert (r["k"] == "1") == (r["method"] == "nn"), r
PY

check "exists without --resume" 1 -- "${sweep[@]}"
out=$("${sweep[@]}" --resume 2>&1)
[[ "$out" == *"32 already in"*"0 to measure"* ]] || fail "resume did not skip all: $out"
head -n -1 "$dir/out/results.csv" > "$dir/cut.csv" && mv "$dir/cut.csv" "$dir/out/results.csv"
out=$("${sweep[@]}" --resume 2>&1)
[[ "$out" == *"31 already in"*"1 to measure"* ]] || fail "resume did not redo the lost row: $out"
[[ $(($(wc -l < "$dir/out/results.csv") - 1)) -eq 32 ]] || fail "resumed CSV should hold 32 rows"
check "resume, other reference" 1 -- "${base[@]}" --reference-spp 32 --resume
check "resume, other footprint" 1 -- "${sweep[@]}" --resume --texture-footprint pixel
check "resume, other fovea" 1 -- "${sweep[@]}" --resume --fovea grid
# The pixel footprint reads sharper textures: the same configurations, other colours.
"$fovbench" "${common[@]}" --scene builtin --scales 2.0 --methods nn --spp 1 --texture-footprint pixel \
  --reference-spp 16 --baselines full,uniform --uniform-fractions 0.25 -o "$dir/pixel" >/dev/null 2>&1 || fail "pixel-footprint sweep"
python3 - "$dir/out/results.csv" "$dir/pixel/results.csv" <<'PY' || fail "pixel footprint rows"
import csv, sys
disc = {(r["gaze"], r["scale"], r["method"], r["spp"]): r for r in csv.DictReader(open(sys.argv[1]))}
pixel = [r for r in csv.DictReader(open(sys.argv[2])) if r["kind"] == "foveated"]
assert len(pixel) == 1 and pixel[0]["texture_footprint"] == "pixel", pixel
d = disc[("centre", "2.00", "nn", "1")]
assert d["points_traced"] == pixel[0]["points_traced"]
assert d["psnr"] != pixel[0]["psnr"], "the footprint changed no colour"
PY

echo "$passes passed, $failures failed"
[[ $failures -eq 0 ]]
