#!/usr/bin/env bash
# The conformance suite when the firmware stops answering (its simulator
# stopped by SIGSTOP just after the ping check) until the suite has given up
# on the request in flight and says it is sending RUN_STOP; the simulator
# then resumes and answers it. The link error says what came in meanwhile
# (nothing) and that the firmware answered again afterwards, which tells a
# pause (a stalled emulator, a rebooting board) from a firmware that died.
#   conformance_stalled_firmware.sh CONSOLE
set -u
console=$1
. "$(dirname "$0")/conformance_suite_prelude.sh"
start_suite --timeout 200
kill -STOP $sim
for _ in $(seq 1500); do grep -q "sending RUN_STOP to see whether" "$work/out.txt" && break; sleep 0.02; done
kill -CONT $sim
end_suite 2 "a link error"
error=$(grep "no reply to .*afterwards" "$work/out.txt")
[ -n "$error" ] || { echo "FAIL: no 'no reply to' error"; exit 1; }
grep -qE "after [0-9] tries \(200(, [0-9]+)* ms\); meanwhile nothing arrived from /dev/pts/[0-9]+" <<<"$error" ||
  { echo "FAIL: the error does not say that nothing arrived meanwhile"; exit 1; }
grep -q "; afterwards the device answered RUN_STOP" <<<"$error" ||
  { echo "FAIL: the error does not say the device answered again"; exit 1; }
exit 0
