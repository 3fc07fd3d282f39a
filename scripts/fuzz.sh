#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, in build-fuzz/) and runs each for
# SECONDS (default 60) from its seed corpus, tests/fuzz/corpus/<target>/. Fails when any
# target finds something: the input is kept in build-fuzz/findings/<target>/ and the
# sanitizer's or the target's report is printed. Inputs a run adds to the corpus stay in
# build-fuzz/corpus/<target>/ and seed the next run. docs/fuzzing.md explains the targets.
#   scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || (( seconds < 1 )); then
  echo "fuzz.sh: SECONDS must be a whole number of seconds, at least 1 (got '$seconds')" >&2
  exit 2
fi
shift $(( $# > 0 ? 1 : 0 ))
all=(pointset protocol session thresholds gaze_trace gaze_datagram pupil_gaze gaze_calibration camera_path results scene env_image
  reference_meta camera_flags)
targets=("${@:-${all[@]}}")
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "fuzz.sh: unknown target '$t' (one of: ${all[*]})" >&2; exit 2; }
done

"$root/scripts/install-deps.sh"
build="$root/build-fuzz"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DFOV_FUZZ=ON >/dev/null
cmake --build "$build" -j "$(nproc)" --target fuzz_targets >&2

# Leaks are not findings here: the libraries' caches (OpenImageIO, TBB) live to exit.
export ASAN_OPTIONS="detect_leaks=0:allocator_may_return_null=0:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:${UBSAN_OPTIONS:-}"
failed=()
printf '%-14s %8s %12s %8s %8s %8s  %s\n' target seconds executions exec/s edges corpus result
for t in "${targets[@]}"; do
  work="$build/corpus/$t" findings="$build/findings/$t" log="$build/logs/$t.log"
  mkdir -p "$work" "$findings" "$(dirname "$log")"
  # Sanitizer reports go to files of their own: the loaders silence stderr around some
  # library reads, and a report printed there would be lost (docs/fuzzing.md).
  report="$build/logs/$t.sanitizer"
  rm -f "$report".*
  set +e
  ASAN_OPTIONS="$ASAN_OPTIONS:log_path=$report" UBSAN_OPTIONS="$UBSAN_OPTIONS:log_path=$report" \
  "$build/tests/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=3072 -malloc_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$findings/" "$work" "$root/tests/fuzz/corpus/$t" >"$log" 2>&1
  rc=$?
  set -e
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)
  edges=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
  units=$(grep -o 'corp: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
  result=clean
  if (( rc != 0 )); then
    result="FINDING (exit $rc): $(ls -t "$findings" | head -n 1)"
    failed+=("$t")
  fi
  printf '%-14s %8s %12s %8s %8s %8s  %s\n' "$t" "$seconds" "${runs:--}" "${rate:--}" "${edges:--}" "${units:--}" "$result"
  if (( rc != 0 )); then
    cat "$report".* >>"$log" 2>/dev/null
    grep -E 'ERROR|fuzz finding|runtime error|SUMMARY|Test unit written' "$log" | head -n 8 | sed 's/^/    /' >&2 || true
    # Where it happened and what did it, in the log itself: a CI machine's files are gone
    # once it ends, and a finding must be reproducible from what it printed.
    grep -E '^ *#[0-9]+ 0x' "$log" | grep -vE 'fuzzer::|__sanitizer|__asan|__interceptor|MallocHook' | head -n 16 \
      | sed 's/^ */    /; s/ (BuildId: [0-9a-f]*)//' >&2 || true  # (a timeout prints no frames)
    input="$findings/$(ls -t "$findings" | head -n 1)"
    if [[ -f "$input" ]] && (( $(stat -c %s "$input") <= 16384 )); then
      echo "    the input ($(stat -c %s "$input") bytes), base64 (decode with base64 -d):" >&2
      base64 -w 100 "$input" | sed 's/^/    /' >&2
    fi
  fi
done
if (( ${#failed[@]} )); then
  echo "fuzz.sh: findings in: ${failed[*]} (inputs in $build/findings/; logs in $build/logs/)" >&2
  echo "fuzz.sh: fix each, then copy its input into tests/fuzz/corpus/<target>/ so ctest replays it" >&2
  exit 1
fi
