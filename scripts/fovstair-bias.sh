#!/usr/bin/env bash
# The staircase rules' bias and spread in estimating a simulated observer's threshold
# (docs/fovstair.md): one `fovstair simulate` per row, printed as a markdown table.
# Usage: scripts/fovstair-bias.sh [RUNS]   (default 1000; run after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-1000}
stair=build/apps/fovstair
p=apps/fovstair/protocols
row() {  # label, protocol, observer, extra simulate flags...
  local label=$1 protocol=$2 observer=$3; shift 3
  "$stair" simulate --protocol "$protocol" --observer "$observer" --runs "$runs" --json "$@" |
    python3 -c 'import json, sys
j = json.load(sys.stdin); label = sys.argv[1]; r = j["rule"]
cells = [label, "%d-up/%d-down" % (r["up"], r["down"]), "%g / %g" % (r["initial_step"], r["step"]), "%g" % r["start"],
         str(r["thresholds"]), j["observer"].split(":")[1], "%.3f" % j["target_scale"], "%.3f" % j["estimate_mean"],
         "%+.3f" % (j["estimate_mean"] - j["target_scale"]), "%.3f" % j["estimate_sd"], "%.1f" % (j["mean_trials_per_run"] / 3)]
print("| " + " | ".join(cells) + " |")' "$label"
}
echo "| variant | rule | steps | start | thresholds | observer | target s | estimate | bias | SD | trials per series |"
echo "|---|---|---|---:|---:|---|---:|---:|---:|---:|---:|"
o=logistic:threshold=1.7,slope=8
row "thesis" $p/thesis.json $o
row "thesis, shallow observer" $p/thesis.json logistic:threshold=1.7,slope=4
row "thesis, steep observer" $p/thesis.json logistic:threshold=1.7,slope=16
row "thesis, 4% lapses" $p/thesis.json logistic:threshold=1.7,slope=8,lapse=0.04
row "thesis, threshold 1.3" $p/thesis.json logistic:threshold=1.3,slope=8
row "thesis, threshold 2.2" $p/thesis.json logistic:threshold=2.2,slope=8
row "half the steps" $p/thesis.json $o --initial-step 0.1 --step 0.05
row "twice the steps" $p/thesis.json $o --initial-step 0.4 --step 0.2
row "descending from 3.0" $p/thesis.json $o --start 3.0
row "8 thresholds, 3 discarded" $p/thesis.json $o --thresholds 8 --discard 3
row "yes-no 1-up/2-down" $p/yesno-1up2down.json $o
row "2AFC 1-up/3-down" $p/2afc-1up3down.json $o
