#!/usr/bin/env bash
# fovview's frame rate at the FOVE screen (1280x1440), headless under Xvfb, as a markdown
# table (docs/fovview.md). Gaze fixed at the centre; medians of 40 frames after 5 warm-up.
# Usage: scripts/fovview-fps.sh   (after scripts/build.sh and precomputed/generate.sh default)
set -euo pipefail
cd "$(dirname "$0")/.."
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
set_file=precomputed/fove-s1.00.fovset
env_scene=env:/usr/share/blender/datafiles/studiolights/world/city.exr
row() {  # label, flags...
  local label=$1; shift
  xvfb-run -a -s "-screen 0 1600x1600x24" build/apps/fovview --points "$set_file" --gaze centre --frames 45 --exit --json "$@" \
    2>/dev/null | python3 -c 'import json, sys
j = json.load(sys.stdin)
print("| %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f |" % (sys.argv[1], j["fps"], j["frame_ms"], j["trace_ms"],
      j["reconstruct_ms"], j["taa_ms"], j["display_ms"]))' "$label"
}
echo "| configuration | fps | frame ms | trace | reconstruct | TAA | display |"
echo "|---|---:|---:|---:|---:|---:|---:|"
row "builtin, Shepard k=5, 1 spp, TAA" --spp 1
row "builtin, Shepard k=5, 4 spp, TAA" --spp 4
row "builtin, NN, 1 spp, no TAA" --spp 1 --method nn --no-taa
row "env:city.exr, Shepard k=5, 1 spp, TAA" --scene "$env_scene" --spp 1
row "env:city.exr, NN, 1 spp, TAA" --scene "$env_scene" --spp 1 --method nn
row "env:city.exr, NN, 1 spp, no TAA" --scene "$env_scene" --spp 1 --method nn --no-taa
