#!/usr/bin/env bash
# The conformance suite when the host stops running the console for 800 ms
# while it feeds the firmware's link watchdog (SIGSTOP, 0.4 s after the
# check before it): the firmware trips, as it must, and the suite tells
# that from a firmware that trips while fed by the step of the firmware's
# clock between two replies; it runs the check again and passes
# (previously: "FAIL watchdog_fed ... run_state 3", as seen under load).
#   conformance_stalled_console.sh CONSOLE
set -u
console=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The console flushes each check's line as it passes, so the check before the
# watchdog's is seen in the file at once (no stdbuf: its LD_PRELOAD breaks
# AddressSanitizer's link order).
"$console" conformance --sim msd >"$work/out.txt" 2>&1 &
pid=$!
for _ in $(seq 1500); do grep -q "tseq_across_runs" "$work/out.txt" && break; sleep 0.02; done
sleep 0.4
kill -STOP $pid
sleep 0.8
kill -CONT $pid
wait $pid
rc=$?
grep -E "watchdog|passed" "$work/out.txt"
[ $rc -eq 0 ] || { echo "FAIL: exit $rc"; cat "$work/out.txt"; exit 1; }
grep -q "^PASS watchdog_fed: " "$work/out.txt" || { echo "FAIL: watchdog_fed"; exit 1; }
grep -q "run 2 of the check" "$work/out.txt" || echo "note: the stop fell outside the feeding, the check ran once"
exit 0
