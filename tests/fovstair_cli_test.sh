#!/usr/bin/env bash
# fovstair's command line: data safety (a crashed session resumes exactly, nothing is
# overwritten), protocol errors with their line, analysis of the thesis's Table 5, and
# the simulated observer.
set -uo pipefail
fovstair=$1
src=$2
fovgen=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
tool=fovstair
source "$(dirname "$0")/cli_check.sh"
protocol=$src/apps/fovstair/protocols/thesis.json
observer=logistic:threshold=1.7,slope=8,lapse=0.02,false_alarm=0.1

check "no subcommand"       2 -- "$fovstair"
check "bad subject"         2 -- "$fovstair" run --protocol "$protocol" --subject "a b" --observer "$observer" --out "$dir/x"
check "subject from a hyphen" 2 -- "$fovstair" run --protocol "$protocol" --subject "-P03" --observer "$observer" --out "$dir/x"
check "hyphenated subject"  0 -- "$fovstair" run --protocol "$protocol" --subject P-03 --observer "$observer" --out "$dir/hyphen"
[[ -f "$dir/hyphen/P-03-1.jsonl" ]] || fail "the session of P-03 is not P-03-1.jsonl"
err=$("$fovstair" run --subject P-03 --resume --out "$dir/hyphen" 2>&1)
[[ "$err" == "fovstair: $dir/hyphen/P-03-1.jsonl: the session is finished; nothing to resume" ]] || fail "resume P-03: $err"
# validate fails (exit 1, one line after the list) while a set the staircase can reach is missing.
sed "s#\"points_dir\": *\"[^\"]*\"#\"points_dir\": \"$dir/no-sets\"#" "$protocol" > "$dir/nosets.json"
grep -q "no-sets" "$dir/nosets.json" || fail "the protocol has no points_dir to point elsewhere"
err=$("$fovstair" validate "$dir/nosets.json" 2>&1 >/dev/null)
[[ $? -eq 1 && "$err" == "fovstair: $dir/nosets.json: "*" point sets missing (listed above); make the family with: fovgen sweep"* ]] \
  || fail "validate with missing sets: $err"
check "bad observer"        2 -- "$fovstair" run --protocol "$protocol" --subject S1 --observer "probit:1" --out "$dir/x"
check "missing protocol"    1 -- "$fovstair" run --protocol "$dir/none.json" --subject S1 --observer "$observer" --out "$dir/x"
printf '{\n  "fovstair_protocol": 1,\n  "conditions": [{"name": "A", "k": 99}]\n}\n' > "$dir/bad.json"
err=$("$fovstair" validate "$dir/bad.json" 2>&1)
[[ "$err" == "fovstair: $dir/bad.json:3: conditions[0].k: must lie in 1..32" ]] || fail "protocol error: $err"
# Hostile protocol files: nesting 100,000 deep (the line map recursed per level and
# crashed), a FIFO (its open blocked forever), a directory, a file over the size bound.
python3 -c "print('{\"fovstair_protocol\":1,\"x\":'+'['*100000+']'*100000+'}')" > "$dir/deep.json"
err=$("$fovstair" validate "$dir/deep.json" 2>&1)
[[ $? -eq 1 && "$err" == "fovstair: $dir/deep.json:1: nested deeper than 32 levels" ]] || fail "deep protocol: $err"
mkfifo "$dir/fifo.json"
err=$(timeout 20 "$fovstair" validate "$dir/fifo.json" 2>&1)
[[ $? -eq 1 && "$err" == *"fifo.json: not a regular file"* ]] || fail "FIFO protocol: $err"
err=$("$fovstair" validate "$dir" 2>&1)
[[ $? -eq 1 && "$err" == *"is a directory"* ]] || fail "directory as protocol: $err"
head -c 2000000 /dev/zero | tr '\0' ' ' > "$dir/big.json"
err=$("$fovstair" validate "$dir/big.json" 2>&1)
[[ $? -eq 1 && "$err" == *"at most 1048576"* ]] || fail "oversized protocol: $err"
check "resume nothing"      1 -- "$fovstair" run --subject S1 --resume --out "$dir/empty" --observer "$observer"

# An uninterrupted session, and the same session killed after 7 trials (with half a line
# written after it, as a crash mid-write leaves) and resumed: the same trials.
check "whole session"       0 -- "$fovstair" run --protocol "$protocol" --subject S2 --observer "$observer" --out "$dir/whole"
"$fovstair" run --protocol "$protocol" --subject S2 --observer "$observer" --out "$dir/crash" --stop-after 7 >/dev/null 2>&1
[[ $? -eq 3 ]] || fail "--stop-after did not stop"
[[ $(wc -l < "$dir/crash/S2-1.jsonl") -eq 8 ]] || fail "crashed session should hold a header and 7 trials"
printf '{"type": "trial", "ind' >> "$dir/crash/S2-1.jsonl"
before=$(md5sum < "$dir/crash/S2-1.jsonl")
check "never overwrite"     1 -- "$fovstair" run --protocol "$protocol" --subject S2 --session 1 --observer "$observer" --out "$dir/crash"
[[ $(md5sum < "$dir/crash/S2-1.jsonl") == "$before" ]] || fail "an existing session was modified"
check "resume"              0 -- "$fovstair" run --subject S2 --resume --out "$dir/crash"
strip() { python3 -c 'import json,sys
for line in open(sys.argv[1]):
    r = json.loads(line); r.pop("time", None); r.pop("started", None); print(json.dumps(r, sort_keys=True))' "$1"; }
cmp -s <(strip "$dir/whole/S2-1.jsonl") <(strip "$dir/crash/S2-1.jsonl") || fail "resumed session differs from the uninterrupted one"
check "resume finished"     1 -- "$fovstair" run --subject S2 --resume --out "$dir/crash"
check "next session"        0 -- "$fovstair" run --protocol "$protocol" --subject S2 --observer "$observer" --out "$dir/crash"
[[ -s "$dir/crash/S2-2.jsonl" ]] || fail "a second run did not start session 2"

# Analysis of sessions: thresholds CSV, plots, JSON.
for s in 3 4 5; do "$fovstair" run --protocol "$protocol" --subject S$s --observer "$observer" --out "$dir/whole" >/dev/null; done
check "analyze sessions"    0 -- "$fovstair" analyze "$dir"/whole/*.jsonl --out-csv "$dir/t.csv"
[[ $(head -1 "$dir/t.csv") == "subject,condition,threshold" && $(wc -l < "$dir/t.csv") -eq 49 ]] || fail "thresholds CSV"
[[ ! -e "$dir/whole/plots" ]] || fail "plots written without --plots"
check "analyze with plots"  0 -- "$fovstair" analyze "$dir"/whole/*.jsonl --plots "$dir/plots" --bootstrap 20
# 4 subjects x 3 conditions: a staircase plot per series (S2 ran one session here) and a
# psychometric plot per subject and condition.
[[ $(ls "$dir"/plots/*-psychometric.png | wc -l) -eq 12 && $(ls "$dir"/plots/*.png | wc -l) -eq 24 ]] ||
  fail "plots: $(ls "$dir/plots")"
check "analyze two files"   0 -- "$fovstair" analyze "$dir/whole/S3-1.jsonl" "$dir/whole/S4-1.jsonl"
# One subject: thresholds and fits, no ANOVA, exit 0.
out=$("$fovstair" analyze "$dir/whole/S3-1.jsonl" --bootstrap 20 2>&1) || fail "one subject: $out"
[[ "$out" == *"no ANOVA: 3 subject means for 3 conditions"* && "$out" == *"S3 NN weibull  alpha"* ]] || fail "one subject: $out"
"$fovstair" analyze "$dir/whole/S3-1.jsonl" --fit logistic --bootstrap 20 --json > "$dir/one.json" || fail "one subject JSON"
python3 - "$dir/one.json" <<'PY' || fail "one subject JSON"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["anova"] is None and "more subject means" in j["anova_note"], j.get("anova_note")
fits = j["psychometric"]
assert len(fits) == 3 and all(len(f["fits"]) == 1 and f["fits"][0]["family"] == "logistic" for f in fits), fits
for f in fits:
    a = f["fits"][0]
    assert f["guess"] <= 0.5 and 0 <= a["lapse"] <= 0.06 and a["bootstrap"] == 20, f
    # Ten trials per series: the interval need not hold alpha (perfectly separated answers
    # make the slope run away), but it lies within alpha's bounds.
    lo, hi = a["alpha_bounds"]
    assert lo <= a["alpha_interval"][0] <= a["alpha_interval"][1] <= hi and lo <= a["alpha"] <= hi, f
PY
# Exports: PsychoPy-style CSV and BIDS _beh.tsv with a sidecar describing every column.
check "export psychopy" 0 -- "$fovstair" export "$dir/whole/S3-1.jsonl" "$dir/whole/S4-1.jsonl" --out "$dir/export"
[[ $(head -1 "$dir/export/S3_thesis_1.csv") == "participant,session,label,thisN,thisTrialN,intensity,response,reversal,catch,key,rt,estimate,date" &&
   $(($(wc -l < "$dir/export/S3_thesis_1.csv") + 1)) -eq $(wc -l < "$dir/whole/S3-1.jsonl") ]] || fail "PsychoPy CSV: $(ls "$dir/export")"
check "export bids" 0 -- "$fovstair" export "$dir/whole/S3-1.jsonl" "$dir/whole/S4-1.jsonl" --format bids --task fov2 --out "$dir/bids"
python3 - "$dir/bids" <<'PY' || fail "BIDS export"
import csv, json, os, sys
root = sys.argv[1]
assert json.load(open(os.path.join(root, "dataset_description.json")))["BIDSVersion"]
beh = os.path.join(root, "sub-S3", "ses-1", "beh", "sub-S3_ses-1_task-fov2_beh")
rows = list(csv.reader(open(beh + ".tsv"), delimiter="\t"))
side = json.load(open(beh + ".json"))
assert side["TaskName"] == "fov2"
assert all(c in side for c in rows[0]), [c for c in rows[0] if c not in side]
assert all(len(r) == len(rows[0]) for r in rows) and len(rows) > 5
assert all(r[rows[0].index("response_time")] == "n/a" for r in rows[1:])  # a simulated observer has no times
PY
sed '1s/"subject":"S3"/"subject":"S-3"/' "$dir/whole/S3-1.jsonl" > "$dir/S-3.jsonl"
err=$("$fovstair" export "$dir/whole/S3-1.jsonl" "$dir/S-3.jsonl" --format bids --out "$dir/bids2" 2>&1)
[[ $? -eq 1 && "$err" == *"subjects 'S3' and 'S-3' would both be BIDS sub-S3"* && ! -e "$dir/bids2/sub-S3" ]] ||
  fail "BIDS label collision: $err"
check "export bad format" 2 -- "$fovstair" export "$dir/whole/S3-1.jsonl" --format xlsx --out "$dir/x"
check "export bad task"   2 -- "$fovstair" export "$dir/whole/S3-1.jsonl" --format bids --task "a b" --out "$dir/x"
check "export no out"     2 -- "$fovstair" export "$dir/whole/S3-1.jsonl"
check "analyze bad --fit"        2 -- "$fovstair" analyze "$dir/whole/S3-1.jsonl" --fit probit
check "analyze huge --bootstrap" 2 -- "$fovstair" analyze "$dir/whole/S3-1.jsonl" --bootstrap 20000
# A simulated session beside a person's: analysed, with a warning naming the simulated one.
python3 - "$dir/whole/S3-1.jsonl" "$dir/person.jsonl" <<'PY'
import json, sys
lines = open(sys.argv[1]).read().splitlines()
h = json.loads(lines[0]); h["observer"] = None
open(sys.argv[2], "w").write("\n".join([json.dumps(h)] + lines[1:]) + "\n")
PY
err=$("$fovstair" analyze "$dir/whole/S4-1.jsonl" "$dir/person.jsonl" --fit none 2>&1 >/dev/null)
[[ "$err" == *"warning: 1 session(s) answered by a simulated observer ($dir/whole/S4-1.jsonl) analysed together with 1 of people"* ]] ||
  fail "no warning for mixed sessions: $err"
echo "not json" > "$dir/junk.jsonl"
check "analyze junk"        1 -- "$fovstair" analyze "$dir/junk.jsonl"

# Corrupt sessions, refused by analyze and --resume alike with the file and line: trials
# duplicated, after the end record, or spliced from a 2AFC session; records that are not
# objects or have fields of the wrong type; a header without its protocol.
"$fovstair" run --protocol "$src/apps/fovstair/protocols/2afc-1up3down.json" --subject S6 --observer "$observer" \
  --out "$dir/two" >/dev/null || fail "2AFC session"
base=$dir/whole/S3-1.jsonl
mkdir -p "$dir/bad"
corrupt() {  # NAME PYTHON-EXPRESSION over `lines` (the base session's lines): writes $dir/bad/NAME.jsonl
  python3 - "$base" "$dir/two/S6-1.jsonl" "$dir/bad/$1.jsonl" "$2" <<'PY'
import json, sys
lines = open(sys.argv[1]).read().splitlines(keepends=True)
two = open(sys.argv[2]).read().splitlines(keepends=True)
out = eval(sys.argv[4])
open(sys.argv[3], "w").write("".join(out))
PY
}
corrupt duplicated  'lines[:3] + lines[2:]'
corrupt after-end   'lines + [lines[2]]'
corrupt spliced     'lines[:2] + [two[1]] + lines[2:]'
corrupt dropped     'lines[:2] + lines[3:]'
corrupt array       'lines[:2] + ["[1,2]\n"] + lines[2:]'
corrupt number      'lines[:2] + ["5\n"] + lines[2:]'
corrupt string      'lines[:2] + ["\"x\"\n"] + lines[2:]'
corrupt null-type   'lines[:2] + ["{\"type\": null}\n"] + lines[2:]'
corrupt number-type 'lines[:2] + ["{\"type\": 7}\n"] + lines[2:]'
corrupt text-scale  '[lines[0], lines[1].replace("\"scale\":1.0", "\"scale\":\"1.0\"")] + lines[2:]'
corrupt no-protocol '[json.dumps({k: v for k, v in json.loads(lines[0]).items() if k != "protocol_text"}) + "\n"] + lines[1:]'
corrupt end-early   'lines[:5] + [lines[-1]]'
for f in "$dir"/bad/*.jsonl; do
  check "analyze $(basename "$f")" 1 -- "$fovstair" analyze "$f"
done
err=$("$fovstair" analyze "$dir/bad/duplicated.jsonl" 2>&1)
[[ "$err" == "fovstair: $dir/bad/duplicated.jsonl:4: trial index 1, the plan's next is 2" ]] || fail "duplicated trial: $err"
err=$("$fovstair" analyze "$dir/bad/spliced.jsonl" 2>&1)
[[ "$err" == *"spliced.jsonl:3: "* ]] || fail "spliced trial: $err"
err=$("$fovstair" analyze "$dir/bad/after-end.jsonl" 2>&1)
[[ "$err" == *"a record after the end record"* ]] || fail "trial after the end: $err"
# --resume reads a session the same way, and a torn header is refused without touching the file.
for name in duplicated array no-protocol; do
  mkdir -p "$dir/resume-$name" && head -n -1 "$dir/bad/$name.jsonl" > "$dir/resume-$name/S3-1.jsonl"
  check "resume $name" 1 -- "$fovstair" run --subject S3 --resume --out "$dir/resume-$name"
done
mkdir -p "$dir/torn" && head -c 300 "$base" > "$dir/torn/S3-1.jsonl"
before=$(md5sum < "$dir/torn/S3-1.jsonl")
check "resume torn header"  1 -- "$fovstair" run --subject S3 --resume --out "$dir/torn"
[[ $(md5sum < "$dir/torn/S3-1.jsonl") == "$before" ]] || fail "--resume changed a session whose header is torn"

# Protocol values beyond their bounds, and integers that would wrap, refused by validate
# with the line and the bound.
protocol_case() {  # NAME EXPECTED-MESSAGE-PART JSON-FRAGMENT (keys added to a valid protocol)
  printf '{"fovstair_protocol": 1, "conditions": [{"name": "A", "method": "nn", "k": 1}],\n %s}\n' "$3" > "$dir/p-$1.json"
  local err
  err=$("$fovstair" validate "$dir/p-$1.json" 2>&1)
  [[ $? -eq 1 && "$err" == "fovstair: $dir/p-$1.json:"*"$2"* && $(printf '%s' "$err" | grep -c '') -eq 1 ]] \
    || fail "protocol $1: $err"
}
protocol_case catch-overflow "beyond the range of a double" '"catch_rate": 1e400'
protocol_case catch-high "must lie in [0, 0.5]" '"catch_rate": 0.9'
protocol_case scale-huge "scales.max: must be at most 10" '"scales": {"min": 1, "max": 1e15}'
protocol_case thresholds-float "must be an integer" '"rule": {"thresholds": 1e9, "max_trials": 1e9}'
protocol_case thresholds-big "rule.thresholds: must lie in 1..100" '"rule": {"thresholds": 1000000000, "max_trials": 1000000000}'
protocol_case trials-big "rule.max_trials: must lie in thresholds..1000" '"rule": {"max_trials": 5000}'
protocol_case up-wrap "rule.up: must be an integer in 0..4294967295" '"rule": {"up": 4294967297}'
protocol_case step-huge "rule.initial_step: must be at most 10" '"rule": {"initial_step": 1e300}'
protocol_case interval "interval_ms: must lie in (0, 60000]" '"interval_ms": 1e12'
printf '{"fovstair_protocol": 1, "conditions": [{"name": "A", "k": 4294967301}]}\n' > "$dir/p-k-wrap.json"
err=$("$fovstair" validate "$dir/p-k-wrap.json" 2>&1)
[[ "$err" == *"conditions[0].k: must be an integer in 0..4294967295"* ]] || fail "k that wraps: $err"
printf '{"fovstair_protocol": 1, "conditions": [{"name": "A", "spp": 1000000000}]}\n' > "$dir/p-spp.json"
err=$("$fovstair" validate "$dir/p-spp.json" 2>&1)
[[ "$err" == *"conditions[0].spp: must lie in 1..1024"* ]] || fail "condition spp: $err"
python3 -c "import json; print(json.dumps({'fovstair_protocol': 1, 'conditions': [{'name': 'c%d' % i} for i in range(65)]}))" \
  > "$dir/p-many.json"
err=$("$fovstair" validate "$dir/p-many.json" 2>&1)
[[ "$err" == *"65 conditions; a protocol may have at most 64"* ]] || fail "65 conditions: $err"
check "simulate too many runs" 2 -- "$fovstair" simulate --protocol "$protocol" --observer logistic:threshold=1.7 --runs 100000

# Thesis Table 5 re-analysed: the thesis's F(2, 48) = 0.403, p = 0.670.
"$fovstair" analyze --thresholds "$src/tests/data/thesis-table5.csv" --json > "$dir/a.json" || fail "analyze --thresholds"
python3 - "$dir/a.json" <<'PY' || fail "Table 5 statistics"
import json, sys
j = json.load(open(sys.argv[1]))
assert abs(j["anova"]["F"] - 0.403) < 5e-4 and abs(j["anova"]["p"] - 0.670) < 5e-4, j["anova"]
assert j["anova"]["df1"] == 2 and j["anova"]["df2"] == 48
assert j["conditions"]["NN"]["n"] == 17 and abs(j["conditions"]["RBF"]["mean"] - 1.675) < 5e-4
assert abs(j["conditions"]["MSM"]["sd"] - 0.362) < 5e-4
PY

# No spread within conditions: F is inf (p = 0) when the conditions differ, 0 (p = 1) when
# they do not; 0/0 printed "F(1, 2) = -nan".
printf 'subject,condition,threshold\nS1,A,1.5\nS2,A,1.5\nS1,B,2\nS2,B,2\n' > "$dir/flat.csv"
out=$("$fovstair" analyze --thresholds "$dir/flat.csv" 2>&1)
[[ "$out" == *"F(1, 2) = inf, p = 0.000"* && "$out" != *nan* ]] || fail "zero-variance ANOVA: $out"
printf 'subject,condition,threshold\nS1,A,2\nS2,A,2\nS1,B,2\nS2,B,2\n' > "$dir/same.csv"
out=$("$fovstair" analyze --thresholds "$dir/same.csv" 2>&1)
[[ "$out" == *"F(1, 2) = 0.000, p = 1.000"* && "$out" != *nan* ]] || fail "identical conditions: $out"

"$fovstair" simulate --protocol "$protocol" --observer logistic:threshold=1.7,slope=8 --runs 200 --json > "$dir/s.json" \
  || fail "simulate"
python3 - "$dir/s.json" <<'PY' || fail "simulate JSON"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["true_threshold"] == 1.7 and j["runs"] == 200, j
assert abs(j["estimate_mean"] - 1.7) < 0.1 and 0 < j["estimate_sd"] < 0.3, j
PY
check "simulate no runs"    2 -- "$fovstair" simulate --protocol "$protocol" --observer logistic:threshold=1.7 --runs 0

# The procedures compared on one observer: each lands within 0.2 of its own target, and a
# wrong --procedure or an up-down override given to QUEST is a flag error.
"$fovstair" simulate --protocol "$src/apps/fovstair/protocols/2afc-quest-plus.json" --observer logistic:threshold=1.7,slope=8 \
  --runs 20 --procedure all --json > "$dir/procs.json" || fail "simulate --procedure all"
python3 - "$dir/procs.json" <<'PY' || fail "simulate --procedure all JSON"
import json, sys
j = json.load(open(sys.argv[1]))["procedures"]
assert [p["procedure"] for p in j] == ["up-down", "quest", "quest-plus"], j
for p in j:
    assert abs(p["bias_from_target"]) < 0.2 and p["incomplete_series"] == 0, p
# 2AFC: up-down defaults to 1-up/3-down, 0.5^(1/3) correct
assert abs(j[1]["target_probability"] - 0.82) < 1e-9 and abs(j[0]["target_probability"] - 0.5 ** (1 / 3)) < 1e-6
PY
check "run bad --screen-ppd"  2 -- "$fovstair" run --protocol "$protocol" --subject S9 --out "$dir/x" --screen-ppd -3
check "run --screen-ppd with --observer" 2 -- "$fovstair" run --protocol "$protocol" --subject S9 --out "$dir/x" \
  --observer "$observer" --screen-ppd 40
check "simulate bad procedure" 2 -- "$fovstair" simulate --protocol "$protocol" --observer logistic:threshold=1.7 --procedure bisect
check "simulate quest with --step" 2 -- "$fovstair" simulate --protocol "$protocol" --observer logistic:threshold=1.7 \
  --procedure quest --step 0.2
# A QUEST+ session answered by the simulated observer: one threshold per condition, and it
# analyses.
"$fovstair" run --protocol "$src/apps/fovstair/protocols/2afc-quest-plus.json" --subject Q-1 --out "$dir/quest" \
  --observer logistic:threshold=1.7,slope=8 > "$dir/quest.txt" || fail "QUEST+ session"
[[ $(grep -c "40 trials, thresholds \[1\.[0-9]*\]" "$dir/quest.txt") == 3 ]] || fail "QUEST+ session: $(cat "$dir/quest.txt")"

# A live session in a window (under Xvfb), answered by a key script: 1.0 no, 1.2 no,
# 1.4 yes (a reversal: 1.4), 1.2 no (a reversal: 1.2), and the series is done.
if ! command -v xvfb-run >/dev/null; then
  echo "SKIP the windowed session: xvfb-run is not installed (scripts/install-deps.sh installs it)"
else
  export XDG_RUNTIME_DIR=$dir
  mkdir -p "$dir/sets"
  for s in 1.00 1.20 1.40; do "$fovgen" --width 64 --height 72 --k 8 --scale $s -o "$dir/sets/64x72-v1-s$s.fovset" >/dev/null; done
  cat > "$dir/live.json" <<JSON
{"fovstair_protocol": 1, "scene": "builtin", "points_dir": "$dir/sets", "display": "64x72", "spp": 1,
 "conditions": [{"name": "SH", "method": "shepard", "k": 5}], "scales": {"min": 1.0, "max": 1.4},
 "rule": {"initial_step": 0.2, "step": 0.2, "discard_reversals": 0, "thresholds": 2}, "catch_rate": 0}
JSON
  check "live without display" 1 -- env -u DISPLAY -u WAYLAND_DISPLAY "$fovstair" run --protocol "$dir/live.json" \
    --subject L2 --out "$dir/live"
  check "live, unreachable display" 1 -- env -u WAYLAND_DISPLAY DISPLAY=:987 timeout 20 "$fovstair" run \
    --protocol "$dir/live.json" --subject L2 --out "$dir/live"
  [[ ! -e "$dir/live/L2-1.jsonl" ]] || fail "a run that could not start left a session file"
  xvfb-run -a -s "-screen 0 800x600x24" "$fovstair" run --protocol "$dir/live.json" --subject L1 --out "$dir/live" \
    --script-keys nnyn >/dev/null 2>"$dir/live.err" || fail "live session: $(cat "$dir/live.err")"
  python3 - "$dir/live/L1-1.jsonl" <<'PY' || fail "live session data"
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
trials = [l for l in lines if l["type"] == "trial"]
assert lines[-1]["type"] == "end", lines[-1]
assert [t["scale"] for t in trials] == [1.0, 1.2, 1.4, 1.2], [t["scale"] for t in trials]
assert [t["threshold"] for t in trials if t["recorded"]] == [1.4, 1.2]
assert all(t["gaze"]["samples"] >= 1 and t["mean_frame_ms"] > 0 for t in trials), trials[0]
assert trials[2]["response"] == "yes" and trials[0]["response"] == "no"
# Every frame's gaze is kept; the fixation target was the gaze, so fixation held.
assert all(len(t["gaze"]["trace"]) == t["gaze"]["samples"] and not t["fixation_broken"] for t in trials), trials[0]["gaze"]
PY
  # Fixation control: a gaze trace far from the target (the corner), repeat once: every
  # trial is shown twice (the script answers both showings alike), the first answer kept in a "repeat" record, the second recorded
  # and marked broken.
  printf 't_ms,x_norm,y_norm\n0,0.02,0.02\n600000,0.02,0.02\n' > "$dir/corner.csv"
  python3 -c 'import json, sys; p = json.load(open(sys.argv[1])); p["fixation_control"] = {"radius_deg": 0.5, "action": "repeat", "max_repeats": 1}; json.dump(p, open(sys.argv[2], "w"))' \
    "$dir/live.json" "$dir/live-fix.json"
  xvfb-run -a -s "-screen 0 800x600x24" "$fovstair" run --protocol "$dir/live-fix.json" --subject L3 --out "$dir/live" \
    --gaze-trace "$dir/corner.csv" --script-keys nnyn >/dev/null 2>"$dir/live.err" || fail "fixation session: $(cat "$dir/live.err")"
  python3 - "$dir/live/L3-1.jsonl" <<'PY' || fail "fixation control"
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
trials = [l for l in lines if l["type"] == "trial"]
repeats = [l for l in lines if l["type"] == "repeat"]
assert [t["scale"] for t in trials] == [1.0, 1.2, 1.4, 1.2], [t["scale"] for t in trials]
assert [r["index"] for r in repeats] == [0, 1, 2, 3], repeats
assert all(t["fixation_broken"] and t["fixation_max_deg"] > 0.5 for t in trials + repeats)
assert "from the fixation target (radius 0.5)" in repeats[0]["reason"], repeats[0]["reason"]
# Each frame: time, x, y, the sample's age (a trace's samples age as the trial runs), no tracker time.
f = trials[0]["gaze"]["trace"][0]
assert len(f) == 5 and f[3] is not None and f[3] >= 0 and f[4] is None, f
PY
  check "analyze with repeats" 0 -- "$fovstair" analyze "$dir/live/L3-1.jsonl" --fit none
  # Practice: two showings at the top scale before the first trial, recorded as practice,
  # then the same session as L1's.
  python3 -c 'import json, sys; p = json.load(open(sys.argv[1])); p["practice"] = {"trials": 2}; p["question"] = "Odd? Y/N"; json.dump(p, open(sys.argv[2], "w"))' \
    "$dir/live.json" "$dir/live-practice.json"
  xvfb-run -a -s "-screen 0 800x600x24" "$fovstair" run --protocol "$dir/live-practice.json" --subject L4 --out "$dir/live" \
    --script-keys ynnnyn >/dev/null 2>"$dir/live.err" || fail "practice session: $(cat "$dir/live.err")"
  python3 - "$dir/live/L4-1.jsonl" <<'PY' || fail "practice records"
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
assert [l["type"] for l in lines[1:3]] == ["practice", "practice"], lines[1]
assert [l["scale"] for l in lines[1:3]] == [1.4, 1.4] and [l["response"] for l in lines[1:3]] == ["yes", "no"]
trials = [l for l in lines if l["type"] == "trial"]
assert [t["scale"] for t in trials] == [1.0, 1.2, 1.4, 1.2], [t["scale"] for t in trials]
PY
  check "analyze with practice" 0 -- "$fovstair" analyze "$dir/live/L4-1.jsonl" --fit none
  # A session quit during its practice resumes the practice where it stopped.
  mkdir -p "$dir/live2" && head -2 "$dir/live/L4-1.jsonl" > "$dir/live2/L4-1.jsonl"
  xvfb-run -a -s "-screen 0 800x600x24" "$fovstair" run --subject L4 --out "$dir/live2" --resume --script-keys ynnyn \
    >/dev/null 2>"$dir/live.err" || fail "practice resumed: $(cat "$dir/live.err")"
  python3 - "$dir/live2/L4-1.jsonl" <<'PY' || fail "practice resumed records"
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
assert [(l["type"], l.get("index")) for l in lines[1:4]] == [("practice", 0), ("practice", 1), ("trial", 0)], lines[1:4]
assert [t["scale"] for t in lines if t["type"] == "trial"] == [1.0, 1.2, 1.4, 1.2] and lines[-1]["type"] == "end"
PY
  # Degrees kept on another screen: --screen-ppd scales frames by its ratio to the protocol
  # display's pixels per degree, recorded in the header.
  xvfb-run -a -s "-screen 0 800x600x24" "$fovstair" run --protocol "$dir/live.json" --subject L5 --out "$dir/live" \
    --script-keys nnyn --screen-ppd 2 --fullscreen >/dev/null 2>"$dir/live.err" || fail "scaled session: $(cat "$dir/live.err")"
  python3 - "$dir/live/L5-1.jsonl" <<'PY' || fail "presentation in the header"
import json, math, sys
h = json.loads(open(sys.argv[1]).readline())["presentation"]
# 64x72 display: 64 v pi/180 pixels per degree (v from the display spec).
assert h["fullscreen"] and h["screen_ppd"] == 2 and 1 < h["scale"] < 3, h
PY
fi

echo "$passes passed, $failures failed"
[[ $failures -eq 0 ]]
