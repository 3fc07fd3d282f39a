#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test with ctest.
# FOV_SANITIZE=1 runs the suite under ASan + UBSan (Debug build in build-sanitize/).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
build=$("$root/scripts/build.sh" | tail -n 1)
cd "$build"
ctest --output-on-failure -j "$(nproc)" "$@"
