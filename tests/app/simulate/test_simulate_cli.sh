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
expect_error "unknown rig 'nope'; rigs in" simulate --platform nope
expect_error "Q takes 1 value" simulate --platform msd --set Q=1,2
expect_error "Q\[0\] = -1 is out of range" simulate --platform msd --set Q=-1
expect_error "unknown parameter 'Qx'" simulate --platform msd --set Qx=1
expect_error "not a number" simulate --platform msd --set Q=abc
expect_error "cannot open model file" simulate --platform msd --model /nonexistent.nlsm
expect_error "PID baseline is defined for msd only" simulate --platform hasel --controller pid
expect_error "unknown reference 'circle'" simulate --platform hasel --reference circle
expect_error "would break a rule" simulate --platform tendon --set Nc=4
json=$("$console" simulate --platform msd --steps 2000 --json) || { echo "FAIL: msd run"; fail=1; }
grep -q '"nrmse"' <<<"$json" || { echo "FAIL: no nrmse in $json"; fail=1; }
csv=$(mktemp)
"$console" simulate --platform tendon --steps 50 --csv "$csv" >/dev/null || { echo "FAIL: tendon csv run"; fail=1; }
[ "$(wc -l <"$csv")" -eq 51 ] || { echo "FAIL: csv has $(wc -l <"$csv") lines, want 51"; fail=1; }
head -1 "$csv" | grep -q "^step,time_s,y_ref0" || { echo "FAIL: csv header"; fail=1; }
rm -f "$csv"
[ $fail -eq 0 ] && echo "simulate CLI: all checks passed"
exit $fail
