#!/usr/bin/env bash
# A shipped rig identified from the console and tracked with the model that
# identification alone gave: `ident --sim RIG --sim-fast --signal SIGNAL
# --duration 10min` (the simulator excites its plant open-loop, the console
# records u, y and the sensors), `train --rig RIG --run 1` with train's
# defaults, then `simulate --rig RIG --model` on the rig's own reference
# (hasel: the Swirl; tendon: the Infinity) on the true plant, whose
# nRMSE over the tracked axes must be at most LIMIT (a fraction).
#   ident_train_swirl.sh CONSOLE RIG SIGNAL LIMIT
set -u
console=$1 rig=$2 signal=$3 limit=$4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
export XDG_CACHE_HOME=$work/cache XDG_DATA_HOME=$work/data
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }

timeout 600 "$console" ident --sim "$rig" --signal "$signal" --duration 10min --sim-fast --seed 3 --db runs.db \
  >ident.txt 2>&1 || { cat ident.txt; echo "FAIL: ident"; exit 1; }
timeout 600 "$console" train --rig "$rig" --run 1 --db runs.db --out ident.nlsm >train.txt 2>&1 ||
  { cat train.txt; echo "FAIL: train --run"; exit 1; }
grep -E "objective|^ +\*|free-run" train.txt
"$console" simulate --rig "$rig" --model ident.nlsm --json >sim.json 2>log.txt ||
  { cat log.txt; echo "FAIL: simulate"; exit 1; }
nrmse=$(json sim.json 'j["nrmse"]')
echo "$rig, ident --signal $signal -> train -> simulate: nRMSE $nrmse over the tracked axes (limit $limit)"
python3 -c "import sys; sys.exit(not (0 < $nrmse <= $limit))" || { echo "FAIL: nRMSE $nrmse above $limit"; exit 1; }
