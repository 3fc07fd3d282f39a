#!/usr/bin/env bash
# fovview's frame rate at the FOVE screen (1280x1440), headless under Xvfb, as a markdown
# table (docs/fovview.md). Gaze fixed at the centre, or moving (a replayed 120 Hz trace);
# medians of 60 frames after 5 warm-up. One row with --pipeline (the next frame traces while
# one is shown).
# Usage: scripts/fovview-fps.sh   (after scripts/build.sh and precomputed/generate.sh default)
set -euo pipefail
cd "$(dirname "$0")/.."
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
set_file=precomputed/fove-s1.00.fovset
env_scene=env:/usr/share/blender/datafiles/studiolights/world/city.exr
# A moving gaze: 120 Hz samples (the FOVE tracker's rate), a fixation every 300 ms at one
# of nine places, 0.3 % of the screen of jitter: every frame's gaze differs.
gaze_file=$(mktemp --suffix .csv)
trap 'rm -f "$gaze_file"' EXIT
python3 - "$gaze_file" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("t_ms,x_norm,y_norm\n")
    for i in range(2400):
        t = i * 1000 / 120
        fx = 0.25 + 0.25 * ((int(t // 300) * 7) % 3); fy = 0.25 + 0.25 * ((int(t // 300) * 5) % 3)
        f.write("%.3f,%.5f,%.5f\n" % (t, fx + 0.003 * math.sin(0.9 * i), fy + 0.003 * math.cos(1.3 * i)))
PY
row() {  # label, flags...
  local label=$1; shift
  xvfb-run -a -s "-screen 0 1600x1600x24" build/apps/fovview --points "$set_file" --frames 65 --exit --json "$@" \
    2>/dev/null | python3 -c 'import json, sys
j = json.load(sys.stdin)
print("| %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f |" % (sys.argv[1], j["fps"], j["frame_ms"], j["trace_ms"],
      j["reconstruct_ms"], j["taa_ms"], j["display_ms"], j["latency_ms"]))' "$label"
}
echo "| configuration | fps | frame ms | trace | reconstruct | TAA | display | gaze-to-screen |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
centre=(--gaze centre)
moving=(--gaze-trace "$gaze_file")
row "builtin, Shepard k=5, 1 spp, TAA" "${centre[@]}" --spp 1
row "builtin, Shepard k=5, 4 spp, TAA" "${centre[@]}" --spp 4
row "builtin, NN, 1 spp, no TAA" "${centre[@]}" --spp 1 --method nn --no-taa
row "env:city.exr, Shepard k=5, 1 spp, TAA" "${centre[@]}" --scene "$env_scene" --spp 1
row "env:city.exr, NN, 1 spp, TAA" "${centre[@]}" --scene "$env_scene" --spp 1 --method nn
row "env:city.exr, NN, 1 spp, no TAA" "${centre[@]}" --scene "$env_scene" --spp 1 --method nn --no-taa
row "env:city.exr, NN, 1 spp, no TAA, moving gaze" "${moving[@]}" --scene "$env_scene" --spp 1 --method nn --no-taa
row "env:city.exr, NN, 1 spp, no TAA, moving gaze, --pipeline" "${moving[@]}" --scene "$env_scene" --spp 1 --method nn --no-taa --pipeline
row "env:city.exr, Shepard k=5, 1 spp, TAA, moving gaze" "${moving[@]}" --scene "$env_scene" --spp 1
