#!/usr/bin/env bash
# Temporal reuse along camera paths (issue 28; docs/reuse.md "Measured: temporal reuse"): the
# built-in scene on a display (default fove) through the s = 1.0 set (Shepard k = 5) at SPP rays
# a point (default 4), along fovrender's --flicker path of FRAMES frames (default 16) with the
# gaze drifting 3 px a frame, three ways: a slow pan (0.15 degrees a frame), a fast turn (1
# degree a frame) and a sideways move (0.02 world units a frame: parallax and disocclusion).
# Each path is traced twice, every point every frame and with --reuse temporal (default
# settings), and compared with converged frames along it (REFERENCE_SPP Sobol rays a pixel,
# default 64; their floor a second seed): rays a frame, flicker and video JOD (FovVideoVDP, the
# gaze per frame), and the trace time of both in turn frame by frame over three more passes
# (median ratio and its range). REUSE adds reuse flags (e.g. "--reuse-fovea 2 --reuse-threshold 0.05") and
# PATHS picks paths (default "slow-pan fast-turn sideways"). TRACE sets how a sample is traced,
# for the frames and their converged references alike (e.g. "--integrator path --bounces 3";
# default the direct integrator). Results in out/reuse/DISPLAY
# (DISPLAY-TAG with TAG set): one JSON a path and summary.md.
set -euo pipefail
cd "$(dirname "$0")/.."
render=${FOV_RENDER:-build/apps/fovrender}
fovgen=${FOV_GEN:-build/apps/fovgen}
display=${1:-fove}
spp=${SPP:-4}
frames=${FRAMES:-16}
reference_spp=${REFERENCE_SPP:-64}
read -r -a reuse <<< "${REUSE:-}"
read -r -a trace <<< "${TRACE:-}"
read -r -a names <<< "${PATHS:-slow-pan fast-turn sideways}"
out=out/reuse/$display${TAG:+-$TAG}
mkdir -p "$out"
hfov=$("$fovgen" displays --display "$display" --json | python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)[0]["fov_deg"][0])')
set_file=out/reuse/$display-s1.0.fovset
[[ -s $set_file ]] || "$fovgen" --display "$display" --scale 1.0 -o "$set_file" > /dev/null
scene=(--scene builtin --sun-irradiance 0.8,0.77,0.7 --hfov "$hfov")
declare -A paths=([slow-pan]="--flicker-yaw 0.15" [fast-turn]="--flicker-yaw 1" [sideways]="--flicker-yaw 0 --flicker-shift 0.02")
for name in "${names[@]}"; do
  json=$out/$name.json
  read -r -a path <<< "${paths[$name]}"
  [[ -s $json ]] || "$render" "${scene[@]}" --points "$set_file" --device cpp --spp "$spp" "${trace[@]}" --reuse temporal "${reuse[@]}" \
    --flicker "$frames" "${path[@]}" --reference-spp "$reference_spp" --no-flip -o "$out/$name.png" --json > "$json"
done
python3 - "$out" "$spp" "$frames" "$reference_spp" "${REUSE:-defaults}" "${TRACE:-direct}" <<'PY' > "$out/summary.md"
import json, os, sys
out, spp, frames, reference_spp, reuse, trace = sys.argv[1:]
print(f"{frames} frames, {spp} rays a point, traced: {trace}, reuse settings: {reuse}; video JOD against converged frames of "
      f"{reference_spp} rays a pixel (floor: a second seed); rays: the mean over frames 1.. (frame 0 has nothing to reuse).\n")
print("| path | kept (share of points) | kept by eccentricity, frame 1..: <5 / 5-10 / 10-15 / 15-30 / >30 degrees | primary rays a frame, full -> reuse (ratio) | every ray, full -> reuse (ratio) | "
      "video JOD full / reuse (floor) | flicker full / reuse | trace time reuse / full: median (min-max), pairs |")
print("|---|---|---|---|---|---|---|---|")
for name in ("slow-pan", "fast-turn", "sideways"):
    if not os.path.exists(f"{out}/{name}.json"):
        continue
    r = json.load(open(f"{out}/{name}.json"))["reuse_path"]
    kept = [f["reused_share"] for f in r["per_frame"][1:]]
    later = r["per_frame"][1:]
    bands = " / ".join(f"{sum(f['by_eccentricity'][b]['reused'] for f in later) / max(1, sum(f['by_eccentricity'][b]['points'] for f in later)):.2f}"
                       for b in range(len(later[0]["by_eccentricity"])))
    print(f"| {name} | {min(kept):.2f}-{max(kept):.2f} | {bands} | {r['rays_full']:.0f} -> {r['rays_reuse']:.0f} ({r['rays_ratio']:.2f}) | "
          f"{r['all_rays_full']:.0f} -> {r['all_rays_reuse']:.0f} ({r['all_rays_ratio']:.2f}) | "
          f"{r['jod_full']:.3f} / {r['jod_reuse']:.3f} ({r['jod_floor']:.2f}) | {r['flicker_full']:.4f} / {r['flicker_reuse']:.4f} | "
          + (f"{t['ratio_median']:.2f} ({t['ratio_min']:.2f}-{t['ratio_max']:.2f}), {t['pairs']} |" if (t := r.get('trace_time')) else "- |"))
PY
cat "$out/summary.md"
