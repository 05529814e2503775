#!/usr/bin/env bash
# The conformance suite when the firmware stops answering for 3 s (its
# simulator stopped by SIGSTOP just after the ping check; 4 tries of 500 ms
# make a request give up after 2 s, and RUN_STOP then waits 2 s more, so any
# request sent in the stop's first second fails and the RUN_STOP after it is
# answered, with a second to spare either side): the link error
# says what came in meanwhile (nothing) and that the firmware answered again
# afterwards, which tells a pause (a stalled emulator, a rebooting board)
# from a firmware that died.
#   conformance_stalled_firmware.sh CONSOLE
set -u
console=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$console" conformance --sim msd --timeout 500 >"$work/out.txt" 2>&1 &
pid=$!
for _ in $(seq 1500); do grep -q "^PASS ping" "$work/out.txt" && break; sleep 0.02; done
sim=$(pgrep -P $pid -f nlsoft-firmware-sim)
[ -n "$sim" ] || { echo "FAIL: no simulator under the console"; cat "$work/out.txt"; kill $pid; exit 1; }
kill -STOP $sim
sleep 3
kill -CONT $sim
wait $pid
rc=$?
cat "$work/out.txt"
[ $rc -eq 2 ] || { echo "FAIL: exit $rc, expected 2 (a link error)"; exit 1; }
error=$(grep "no reply to " "$work/out.txt")
[ -n "$error" ] || { echo "FAIL: no 'no reply to' error"; exit 1; }
grep -qE "after [0-9] tries of 500 ms; meanwhile nothing arrived from /dev/pts/[0-9]+" <<<"$error" ||
  { echo "FAIL: the error does not say that nothing arrived meanwhile"; exit 1; }
grep -q "; afterwards the device answered RUN_STOP" <<<"$error" ||
  { echo "FAIL: the error does not say the device answered again"; exit 1; }
exit 0
