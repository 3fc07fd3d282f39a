#!/usr/bin/env bash
# Up-down vs QUEST vs QUEST+ on the same simulated 2AFC observers (docs/fovstair.md): each
# procedure's estimate against the scale where that observer reaches the procedure's own
# target probability. One `fovstair simulate` per row, printed as a markdown table.
# Usage: scripts/fovstair-procedures.sh [RUNS]   (default 1000; run after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-1000}
stair=build/apps/fovstair
p=apps/fovstair/protocols
row() {  # label, protocol, observer, extra simulate flags...
  local label=$1 protocol=$2 observer=$3; shift 3
  "$stair" simulate --protocol "$protocol" --observer "$observer" --runs "$runs" --json "$@" |
    python3 -c 'import json, sys
j = json.load(sys.stdin); label = sys.argv[1]
cells = [label, j["observer"].split(":")[1].replace(",lapse=0,", ",").replace(",false_alarm=0", ""), "%.3f" % j["target_probability"], "%.3f" % j["target_scale"],
         "%.3f" % j["estimate_mean"], "%+.3f" % j["bias_from_target"], "%.3f" % j["estimate_sd"], "%.3f" % j["rmse_from_target"],
         "%.1f" % j["mean_trials_per_series"], str(j["incomplete_series"])]
print("| " + " | ".join(cells) + " |")' "$label"
}
echo "| procedure | observer | target P | target s | estimate | bias | SD | RMSE | trials per series | incomplete |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"
for o in threshold=1.7,slope=8 threshold=1.7,slope=4 threshold=1.7,slope=16 threshold=1.3,slope=8 threshold=2.2,slope=8 \
         threshold=1.7,slope=8,lapse=0.04; do
  row "up-down 1-up/3-down" $p/2afc-1up3down.json "logistic:$o"
  row "QUEST (PsychoPy defaults)" $p/2afc-quest.json "logistic:$o"
  row "QUEST+ (slope 3.5 fixed)" $p/2afc-quest.json "logistic:$o" --procedure quest-plus
  row "QUEST+ (slope, lapse grid)" $p/2afc-quest-plus.json "logistic:$o"
done
