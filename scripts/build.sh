#!/usr/bin/env bash
# Configures and builds fovray. Release by default; FOV_SANITIZE=1 builds a
# Debug tree with AddressSanitizer + UndefinedBehaviorSanitizer in build-sanitize/.
# Prints the build directory on its last line.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [[ "${FOV_SANITIZE:-0}" == "1" ]]; then
  build="$root/build-sanitize"
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DFOV_SANITIZE=ON >/dev/null
else
  build="$root/build"
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="${CMAKE_BUILD_TYPE:-Release}" >/dev/null
fi
cmake --build "$build" -j "$(nproc)" >&2
echo "$build"
