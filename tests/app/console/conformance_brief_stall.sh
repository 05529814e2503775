#!/usr/bin/env bash
# The conformance suite when the host leaves the firmware unscheduled for
# 1.5 s (its simulator stopped by SIGSTOP just after the ping check), as a
# loaded machine does: with --timeout 200 the request in flight is sent at
# 0, 200, 600 and 1400 ms and waited for until 3 s, so the simulator's
# answer when it resumes is taken, the suite passes, and its summary says
# how many requests needed a retry and the longest wait. (Four tries of a
# fixed 200 ms gave up after 800 ms: a link error for a pause.)
#   conformance_brief_stall.sh CONSOLE
set -u
console=$1
. "$(dirname "$0")/conformance_suite_prelude.sh"
start_suite --timeout 200
kill -STOP $sim
sleep 1.5
kill -CONT $sim
end_suite 0 "every check passed"
grep -qE "^PASS reply_seq: .*; [0-9]+ requests? answered only after a retry \(longest wait [0-9]+ ms\)" "$work/out.txt" ||
  { echo "FAIL: the summary does not count the requests answered after a retry"; exit 1; }
wait_ms=$(grep -oE "longest wait [0-9]+ ms" "$work/out.txt" | grep -oE "[0-9]+")
[ "$wait_ms" -ge 600 ] || { echo "FAIL: longest wait $wait_ms ms, yet the simulator was stopped for 1500 ms"; exit 1; }
exit 0
