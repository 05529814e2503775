#!/usr/bin/env bash
# A lab's rig identified from the console, as the paper's method starts:
# my.toml (tests/app/rig/stage.toml, not one of rigs/: 3 inputs, 2 outputs, 5 sensors,
# 80 Hz, a generic plant standing in for the rig) is excited open-loop by
# the firmware (`ident --sim my.toml --signal prbs --duration 10min
# --sim-fast`: the simulator drives the inputs, the console records u, the
# measured y and the sensors), the forward model is trained from that run
# alone (`train --run`), uploaded to the firmware in a session that tracks
# an Infinity, and tracks it on the true plant at nRMSE <= 5 % of the span
# (the session's run, and `simulate --rig --model`).
#   ident_train_track.sh CONSOLE RIG_FILE
set -u
console=$1
fixture=$2  # tests/app/rig/stage.toml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
export XDG_CACHE_HOME=$work/cache XDG_DATA_HOME=$work/data
fail=0
say() { echo "FAIL: $*"; fail=1; }
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }

cp "$fixture" my.toml || exit 1

timeout 300 "$console" ident --sim my.toml --signal prbs --duration 10min --sim-fast --seed 3 --db runs.db \
  >ident.txt 2>&1 || { cat ident.txt; echo "FAIL: ident"; exit 1; }
"$console" runs show 1 --json --db runs.db >ident.json 2>log.txt || { cat log.txt; echo "FAIL: runs show"; exit 1; }
echo "ident: $(json ident.json 'j["samples"]') samples"
# 80 Hz for 10 simulated minutes, every one recorded.
[ "$(json ident.json 'j["samples"]')" = 48000 ] || say "ident recorded $(json ident.json 'j["samples"]') samples, not 48000"

"$console" train --rig my.toml --run 1 --db runs.db --out ident.nlsm --epochs 60 >train.txt 2>&1 ||
  { cat train.txt; echo "FAIL: train --run"; exit 1; }
grep -q "free-run" train.txt || say "train printed no fit: $(cat train.txt)"
hash=$("$console" model info ident.nlsm | sed -n 's/^ *hash 0x\([0-9a-f]*\)$/\1/p')
[ -n "$hash" ] || { echo "FAIL: no hash from model info"; exit 1; }

# The model trained from the run alone, uploaded, tracking an Infinity.
printf 'model upload ident.nlsm\nref infinity\nrun 20s label=track\nexpect lost_frames == 0\n' >track.nls
timeout 300 "$console" --sim my.toml --sim-fast --db runs.db --script track.nls >session.txt 2>&1 ||
  say "--sim my.toml --script: $(tail -5 session.txt)"
grep -q "model ident.nlsm in force: hash $hash confirmed" session.txt || say "no model confirmed: $(cat session.txt)"
"$console" runs show 2 --json --db runs.db >track.json 2>log.txt || say "runs show 2: $(cat log.txt)"
# The worst axis's RMSE of the true plant's output against the span (20 mm).
live=$(json track.json 'max(j["rmse"]) / 20.0 if isinstance(j["rmse"], list) else j["rmse"] / 20.0')
echo "session: Infinity tracked at nRMSE $live of the output span (signal $(json track.json 'j["tracking_signal"]'))"
[ "$(json track.json 'j["tracking_signal"]')" = y_true ] || say "the run was scored on the prediction"
python3 -c "import sys; sys.exit(not (0 < $live <= 0.05))" || say "session: nRMSE $live of the span, above 5 %"

"$console" simulate --rig my.toml --model ident.nlsm --reference infinity --json >sim.json 2>log.txt ||
  { cat log.txt; echo "FAIL: simulate"; exit 1; }
worst=$(json sim.json 'max(e / 20.0 for e in j["rmse"])')
echo "simulate: Infinity tracked at nRMSE $worst of the output span"
python3 -c "import sys; sys.exit(not (0 < $worst <= 0.05))" || say "simulate: nRMSE $worst of the span, above 5 %"
exit $fail
