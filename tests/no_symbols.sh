#!/usr/bin/env bash
# The layering holds in the binaries: no_symbols.sh WHAT REGEX BINARY CONTROL passes when
# BINARY holds no function symbol matching REGEX (nm -C) while CONTROL, which does link
# WHAT, shows them (so the check can fail). interp's tests hold neither Embree (rtc*) nor
# OpenCV (cv::) functions.
set -uo pipefail
what=$1 regex=$2 binary=$3 control=$4
count() { nm -C "$1" 2>/dev/null | grep -cE " [TtUuWw] $regex" || true; }
n=$(count "$binary")
c=$(count "$control")
echo "$what symbols: $n in $(basename "$binary"), $c in $(basename "$control")"
[[ $c -gt 0 ]] || { echo "FAIL the check finds no $what symbol even in $(basename "$control")"; exit 1; }
[[ $n -eq 0 ]] || { nm -C "$binary" | grep -E " [TtUuWw] $regex" | head -5; echo "FAIL $(basename "$binary") holds $what symbols"; exit 1; }
echo "1 passed, 0 failed"
