#!/usr/bin/env bash
# `nlsoft-console simulate` as a user runs it: good runs print metrics, bad
# input exits 2 with a message that names the problem.
set -u
console=$1
fail=0
expect_error() {  # expect_error "pattern" args...
  local pattern=$1; shift
  out=$("$console" "$@" 2>&1); rc=$?
  if [ $rc -ne 2 ] || ! grep -q -- "$pattern" <<<"$out"; then
    echo "FAIL: '$*' gave rc=$rc: $out"; fail=1
  fi
}
expect_error "unknown rig 'nope'; rigs in" simulate --rig nope
expect_error "Q takes 1 value" simulate --rig msd --set Q=1,2
expect_error "Q\[0\] = -1 is out of range" simulate --rig msd --set Q=-1
expect_error "unknown parameter 'Qx'" simulate --rig msd --set Qx=1
expect_error "not a number" simulate --rig msd --set Q=abc
expect_error "cannot open model file" simulate --rig msd --model /nonexistent.nlsm
expect_error "has no \[pid\] table" simulate --rig hasel --controller pid
expect_error "unknown reference 'circle'" simulate --rig hasel --reference circle
expect_error "would break a rule" simulate --rig tendon --set Nc=4
json=$("$console" simulate --rig msd --steps 2000 --json) || { echo "FAIL: msd run"; fail=1; }
grep -q '"nrmse"' <<<"$json" || { echo "FAIL: no nrmse in $json"; fail=1; }
csv=$(mktemp)
"$console" simulate --rig tendon --steps 50 --csv "$csv" >/dev/null || { echo "FAIL: tendon csv run"; fail=1; }
[ "$(wc -l <"$csv")" -eq 51 ] || { echo "FAIL: csv has $(wc -l <"$csv") lines, want 51"; fail=1; }
head -1 "$csv" | grep -q "^step,time_s,y_ref0" || { echo "FAIL: csv header"; fail=1; }
rm -f "$csv"
# --svg draws the run as `runs plot` draws a recorded one (gnuplot), named
# by what was simulated; --svg with --png is refused.
if command -v gnuplot >/dev/null; then
  svg=$(mktemp --suffix=.svg)
  out=$("$console" simulate --rig hasel --steps 400 --svg "$svg" 2>&1) || { echo "FAIL: hasel --svg: $out"; fail=1; }
  grep -q "simulation drawn to $svg" <<<"$out" || { echo "FAIL: no 'drawn to' in: $out"; fail=1; }
  grep -q "<svg" "$svg" && grep -q "simulate swirl on hasel" "$svg" || { echo "FAIL: $svg is not the simulation's picture"; fail=1; }
  # Its axes carry the rig's output names and units, its legend the inputs' names.
  for label in '>x (mm)<' '>z (mm)<' 'output y1: y (mm)' '>u0 h1<'; do
    grep -qF "$label" "$svg" || { echo "FAIL: no '$label' in the simulation's picture"; fail=1; }
  done
  rm -f "$svg"
else
  echo "SKIP: simulate --svg (gnuplot is not installed: apt-get install gnuplot-nox)"
fi
expect_error "give --svg FILE or --png FILE, not both" simulate --rig msd --svg a.svg --png a.png
# Above the README's 5 % target, the table says so; within it, nothing.
out=$("$console" simulate --rig hasel --set Lambda=1e12,1e12,1e12,1e12,1e12,1e12 2>&1)
grep -q "above the 5 % target" <<<"$out" || { echo "FAIL: a poor tracking (Lambda 1e12) is not called above the target: $out"; fail=1; }
out=$("$console" simulate --rig tendon 2>&1)
! grep -q "above the 5 % target" <<<"$out" || { echo "FAIL: tendon's Infinity (0.64 %) called above the target: $out"; fail=1; }
# One value for a parameter of several elements sets them all, as a
# script's `set Lambda 1e8` does (hasel: six actuators).
expect_error "Lambda takes 6 values" simulate --rig hasel --steps 200 --set Lambda=1,2
out=$("$console" simulate --rig hasel --steps 200 --set Lambda=1e8 --json 2>&1) ||
  { echo "FAIL: --set Lambda=1e8 refused: $out"; fail=1; }
# The input metrics of runs and tune, under the same names, with each
# actuator's share of steps at a limit.
for key in '"u_effort"' '"u_saturated"' '"u_saturated_per_input":\[[^]]*,[^]]*,[^]]*,[^]]*,[^]]*,[^]]*\]'; do
  grep -q "$key" <<<"$out" || { echo "FAIL: no $key in simulate --json: $out"; fail=1; }
done
# Inputs that ride their limits are named: msd's force held to +-1 N/kg
# cannot follow its steps.
out=$("$console" simulate --rig msd --steps 2000 --set u_min=-1 --set u_max=1 2>&1) || { echo "FAIL: msd clipped: $out"; fail=1; }
grep -q "at a limit: " <<<"$out" || { echo "FAIL: no input line in: $out"; fail=1; }
grep -q "rides its limit" <<<"$out" || { echo "FAIL: an input pinned at its limit is not said: $out"; fail=1; }
json=$("$console" simulate --rig msd --steps 2000 --set u_min=-1 --set u_max=1 --json 2>/dev/null)
python3 -c 'import json,sys; j=json.loads(sys.argv[1]); assert j["u_saturated"] > 0.5 and j["u_saturated_per_input"][0] == j["u_saturated"], j' "$json" ||
  { echo "FAIL: u_saturated of a clipped msd: $json"; fail=1; }
out=$("$console" simulate --rig msd --steps 2000 2>&1)
! grep -q "rides its limit" <<<"$out" || { echo "FAIL: msd within its limits said to ride them: $out"; fail=1; }
[ $fail -eq 0 ] && echo "simulate CLI: all checks passed"
exit $fail
