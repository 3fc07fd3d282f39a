#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test with ctest.
# FOV_SANITIZE=1 runs the suite under ASan + UBSan (Debug build in build-sanitize/).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
build=$("$root/scripts/build.sh" | tail -n 1)
cd "$build"
# --no-tests=error: a configure that loses the test tree must fail, not pass with nothing run.
ctest --output-on-failure --no-tests=error -j "$(nproc)" "$@"
