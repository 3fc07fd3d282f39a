#!/usr/bin/env bash
# interp links the plain types, never the tracer: its test binary ($1) must hold no Embree
# function (rtc*), while a binary that does link the tracer ($2) shows them (so the check
# can fail).
set -uo pipefail
count() { nm -C "$1" 2>/dev/null | grep -cE ' [TtUuWw] rtc[A-Z]' || true; }
interp=$(count "$1")
tracer=$(count "$2")
echo "rtc symbols: $interp in $(basename "$1"), $tracer in $(basename "$2")"
[[ $tracer -gt 0 ]] || { echo "FAIL the check finds no rtc symbol even in $(basename "$2")"; exit 1; }
[[ $interp -eq 0 ]] || { nm -C "$1" | grep -E ' [TtUuWw] rtc[A-Z]' | head -5; echo "FAIL $(basename "$1") holds Embree symbols"; exit 1; }
echo "1 passed, 0 failed"
