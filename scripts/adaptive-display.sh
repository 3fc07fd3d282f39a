#!/usr/bin/env bash
# Nested sets on a large display (issue 26; docs/adaptive.md "On the largest display"): a
# nested set and single-scale sets as k-NN cells (the encoding whose memory grows with the
# points, the only one whose neighbours fit a 70-ppd canvas in a device buffer), with their
# generation (wall, peak memory), file size, neighbours in memory and loading (fovrender:
# the set's load, and for the nested set the levels' set-up for --adaptive); then per-frame
# cost on the built-in scene at a centred gaze: an adaptive frame, the nested set's finest
# level as a fixed set and the single-scale s = 1.0 set, each paired with the full-resolution
# frame at the same spp (fovrender --speedup), with the process's peak memory.
#   scripts/adaptive-display.sh [DISPLAY] [OUT] [SPP]    (defaults: retinal out/adaptive-display 1)
# Prints markdown tables; the raw JSON and logs stay in OUT. Sets already in OUT are reused.
set -euo pipefail
cd "$(dirname "$0")/.."
display=${1:-retinal}
out=${2:-out/adaptive-display}/$display
spp=${3:-1}
pairs=${PAIRS:-3}
gen=build/apps/fovgen render=build/apps/fovrender
"$gen" displays --display "$display" > /dev/null  # a wrong display: fovgen's one line, exit 2
mkdir -p "$out"
levels=0.7,1.0,1.5,2.25,3.0
timed() {  # timed LABEL COMMAND...: wall seconds and peak kB to LABEL.time, stdout to LABEL.json
  local label=$1
  shift
  /usr/bin/time -f "%e %M" -o "$out/$label.time" "$@" > "$out/$label.json" 2> "$out/$label.log"
}
nested=$out/nested.fovset
[[ -s $nested ]] || timed gen-nested "$gen" --display "$display" --levels $levels --k 8 --seed 1 --encoding cells -o "$nested" --json
for s in 0.70 1.00 3.00; do
  [[ -s $out/s$s.fovset ]] || timed gen-s$s "$gen" --display "$display" --scale $s --k 8 --seed 1 --encoding cells -o "$out/s$s.fovset" --json
done
for name in nested s0.70 s1.00 s3.00; do
  extra=(); [[ $name == nested ]] && extra=(--adaptive)
  timed load-$name "$render" --points "$out/$name.fovset" --spp 1 --no-warmup "${extra[@]}" -o "$out/load.png" --json
  "$gen" info "$out/$name.fovset" --json > "$out/info-$name.json"
done
frame() {  # frame LABEL SET FLAGS...
  local label=$1 set=$2
  shift 2
  timed frame-$label "$render" --scene builtin --points "$set" --gaze centre --spp "$spp" --k 8 --speedup "$pairs" "$@" \
    -o "$out/frame-$label.png" --json
}
frame adaptive0.5 "$nested" --adaptive --adaptive-threshold 0.5
frame level4 "$nested" --level 4
frame s1.00 "$out/s1.00.fovset"

python3 - "$out" "$display" "$spp" <<'PY'
import json, os, sys
out, display, spp = sys.argv[1], sys.argv[2], sys.argv[3]
def load(name):
    with open(os.path.join(out, name)) as f:
        return json.load(f)
def time_of(label):
    wall, kb = open(os.path.join(out, label + ".time")).read().split()[-2:]
    return float(wall), float(kb) / 1024
print(f"### Files and set-up ({display}, k-NN cells, k = 8)\n")
print("| set | points | file MB | generation s | generation peak MB | neighbours in memory MB | load ms | levels setup ms | load peak MB |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
for name in ["nested", "s0.70", "s1.00", "s3.00"]:
    info, ld = load(f"info-{name}.json"), load(f"load-{name}.json")
    gen_label = "gen-" + name
    g = time_of(gen_label) if os.path.exists(os.path.join(out, gen_label + ".time")) else (float("nan"), float("nan"))
    lw, lpeak = time_of("load-" + name)
    print(f"| {name}.fovset | {info['points_total']:,} | {os.path.getsize(os.path.join(out, name + '.fovset')) / 1e6:.1f} | "
          f"{g[0]:.0f} | {g[1]:.0f} | {info.get('knn_memory_bytes', 0) / 1e6:.0f} | {ld['set_load_ms']:.0f} | "
          f"{ld.get('levels_setup_ms', 0):.0f} | {lpeak:.0f} |")
print(f"\n### Frames (built-in scene, centred gaze, {spp} spp, Shepard k = 8)\n")
print("| frame | rays | frame ms (min-max) | full-resolution ms | speedup (95 % interval) | trace ms, written frame | reconstruct ms, written frame | process peak MB |")
print("|---|---:|---:|---:|---:|---:|---:|---:|")
for label in ["adaptive0.5", "level4", "s1.00"]:
    j = load(f"frame-{label}.json")
    _, peak = time_of("frame-" + label)
    print(f"| {label} | {j['rays']:,} | {j['frame_ms']:.0f} ({j['frame_ms_lo']:.0f}-{j['frame_ms_hi']:.0f}) | {j['full_ms']:.0f} | "
          f"{j['speedup']:.2f} ({j['speedup_interval'][0]:.2f}-{j['speedup_interval'][1]:.2f}) | {j['trace_ms']:.0f} | {j['reconstruct_ms']:.0f} | {peak:.0f} |")
PY
