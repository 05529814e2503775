#!/usr/bin/env bash
# A shipped rig identified from the console alone, the path the README
# documents: `ident --sim RIG --signal SIGNAL --duration 10min --sim-fast`
# (the simulator excites its plant open-loop, the console records the run),
# `train --rig RIG --run 1` with train's defaults, then `simulate --rig RIG
# --model` on the rig's own reference (hasel: the Swirl; tendon: the
# Infinity), whose true-plant nRMSE over the tracked axes must be at most
# MAX. Under the sanitizers (--sanitized) training gets 10 L-BFGS
# evaluations and the path is checked for memory faults, not for its fit.
#   shipped_ident_track.sh CONSOLE RIG SIGNAL MAX [--sanitized]
set -u
console=$1 rig=$2 signal=$3 max=$4 sanitized=${5:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
export XDG_CACHE_HOME=$work/cache XDG_DATA_HOME=$work/data
train_args=()
[ "$sanitized" = --sanitized ] && train_args=(--lbfgs 10 --epochs 5)

timeout 600 "$console" ident --sim "$rig" --signal "$signal" --duration 10min --sim-fast --seed 3 --db runs.db \
  >ident.txt 2>&1 || { cat ident.txt; echo "FAIL: ident"; exit 1; }
"$console" train --rig "$rig" --run 1 --db runs.db --out ident.nlsm "${train_args[@]}" >train.txt 2>&1 ||
  { cat train.txt; echo "FAIL: train --run"; exit 1; }
grep -E "^ +\*" train.txt || { cat train.txt; echo "FAIL: train named no kept candidate"; exit 1; }
"$console" simulate --rig "$rig" --model ident.nlsm --json >sim.json 2>log.txt ||
  { cat log.txt; echo "FAIL: simulate"; exit 1; }
nrmse=$(python3 -c "import json; print(json.load(open('sim.json'))['nrmse'])")
echo "$rig, ident --signal $signal -> train -> simulate: nRMSE $nrmse over the tracked axes"
[ "$sanitized" = --sanitized ] && exit 0
python3 -c "import sys; sys.exit(not (0 < $nrmse <= $max))" || { echo "FAIL: nRMSE $nrmse, above $max"; exit 1; }
