#!/usr/bin/env bash
# Where foveation pays, display by display (issue 24; docs/speed-accuracy.md "Across
# displays"): the built-in scene on FOVE (22 ppd), Quest 3 (25), Vision Pro (34), Varjo XR-4
# (51) and a 70-ppd retinal panel (docs/displays.md), each with the camera's horizontal field
# of view set to the display's, the full pixel grid at a foveated sampling rate (rays falling
# from each spp at a centred gaze to a floor of 1 or 2, --ray-floors) against full resolution
# at 1-16 spp, judged in JOD against a 128-spp converged reference with its noise floor.
# Sparse sets are left out (--no-sparse): scripts/sparse-displays.sh measures them (as k-NN cells).
#   out/displays/DISPLAY/   results.csv, report.md (its verdict) and figures per display
# Interrupted? Run it again: --resume keeps every finished row.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=${FOV_BENCH:-build/apps/fovbench}
fovgen=${FOV_GEN:-build/apps/fovgen}
for display in fove quest3 vision-pro varjo-xr4 retinal; do
  hfov=$("$fovgen" displays --display "$display" --json | python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)[0]["fov_deg"][0])')
  "$bench" --scene builtin --sun-irradiance 0.8,0.77,0.7 --display "$display" --hfov "$hfov" --no-sparse --scales 1.0 \
    --methods nn --ray-floors 1,2 --spp 1,2,4,8,16 --baselines full --gazes centre --frames 3 --reference-spp 128 \
    --no-flip --resume -o "out/displays/$display"
done
# summary.md and speedup-vs-ppd.png/.svg: each display's verdict lines (report.md) by pixels
# per degree: at the JOD of full resolution at N spp, the fastest falloff configuration that
# reaches it and its chained speedup with the 95 % interval, or how far short the best falls.
/usr/bin/python3 - out/displays <<'PY'
import csv, json, os, re, subprocess, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
root = sys.argv[1]
at = re.compile(r"^- At ([0-9.]+) JOD \(full resolution, (\d+) spp\) the best foveated configuration, (.+?) \(([0-9.]+) JOD\), "
                r"is ([0-9.]+)x as fast \(95 % interval ([0-9.]+)-([0-9.]+)\)")
short = re.compile(r"^- No foveated configuration reaches ([0-9.]+) JOD \(full resolution, (\d+) spp\); the best reaches ([0-9.]+) \((.+?)\)")
lines, points = [], {}
lines.append("| display | ppd | pixels (M) | full resolution 1 / 2 / 4 / 8 / 16 spp (JOD) | reference floor (JOD) | "
             "at full 1 spp's JOD | at full 2 spp's JOD | at full 4 spp's JOD |")
lines.append("|---|---:|---:|---|---:|---|---|---|")
for display in ("fove", "quest3", "vision-pro", "varjo-xr4", "retinal"):
    path = os.path.join(root, display)
    if not os.path.exists(os.path.join(path, "report.md")):
        continue
    rows = list(csv.DictReader(open(os.path.join(path, "results.csv"))))
    full = {int(r["spp"]): float(r["jod"]) for r in rows if r["kind"] == "full"}
    ppd = float(rows[0]["ppd"])
    pixels = int(rows[0]["full_rays"]) / int(rows[0]["spp"]) / 1e6
    cells = {}
    for line in open(os.path.join(path, "report.md")):
        if m := at.match(line):
            spp = int(m.group(2))
            cells[spp] = f"{m.group(3)}: {m.group(5)}x ({m.group(6)}-{m.group(7)})"
            points.setdefault(spp, []).append((ppd, float(m.group(5)), float(m.group(6)), float(m.group(7))))
        elif m := short.match(line):
            cells[int(m.group(2))] = f"not reached (best {m.group(3)}, {m.group(4)})"
    floor = float(rows[0]["noise_floor_jod"])
    lines.append(f"| `{display}` | {ppd:.1f} | {pixels:.1f} | " + " / ".join(f"{full[s]:.2f}" for s in sorted(full)) +
                 f" | {floor:.2f} | " + " | ".join(cells.get(s, "") for s in (1, 2, 4)) + " |")
open(os.path.join(root, "summary.md"), "w").write("\n".join(lines) + "\n")
fig, ax = plt.subplots(figsize=(6.4, 4.2))
for spp, pts in sorted(points.items()):
    pts.sort()
    x = [p[0] for p in pts]; y = [p[1] for p in pts]
    ax.errorbar(x, y, yerr=[[p[1] - p[2] for p in pts], [p[3] - p[1] for p in pts]], marker="o", capsize=3,
                label=f"at full resolution {spp} spp's JOD")
ax.axhline(1, color="grey", lw=0.8)
ax.set_xlabel("pixels per degree at the display's centre")
ax.set_ylabel("speedup of the fastest falloff frame\nreaching that JOD (95 % interval)")
ax.set_title("Built-in scene: the full grid at a foveated sampling rate")
ax.legend(fontsize=8)
fig.tight_layout()
for ext in ("png", "svg"):
    fig.savefig(os.path.join(root, "speedup-vs-ppd." + ext), dpi=120)
print(open(os.path.join(root, "summary.md")).read())
PY
