#!/usr/bin/env bash
# The conformance suite when the firmware stops for 1.5 s mid-conversation,
# as on a host that leaves it unscheduled: the simulator (a wrapper adds
# --pause-after 20 --pause-ms 1500) stops after its 20th frame, inside the
# parameter checks, at that point however loaded the machine is. At
# --timeout 200 the request in flight is sent at 0, 200, 600 and 1400 ms
# and waited for until 3 s, so the answer it gets when the simulator resumes
# is taken, the suite passes, and its summary says how many requests needed
# a retry, the longest wait and the request that waited. (Four tries of a fixed 200 ms gave up after
# 800 ms: a link error for a pause.)
#   conformance_brief_stall.sh CONSOLE
set -u
console=$1
. "$(dirname "$0")/conformance_suite_prelude.sh"
printf '#!/bin/sh\nexec "%s" --pause-after 20 --pause-ms 1500 "$@"\n' "$NLSOFT_FIRMWARE_SIM" >"$work/paused-sim"
chmod +x "$work/paused-sim"
NLSOFT_FIRMWARE_SIM="$work/paused-sim" "$console" conformance --sim msd --timeout 200 >"$work/out.txt" 2>&1 &
pid=$!
end_suite 0 "every check passed"
grep -qE "^PASS reply_seq: .*; [0-9]+ requests? answered only after a retry \(longest wait [0-9]+ ms, for [A-Z_]+ seq [0-9]+\)" "$work/out.txt" ||
  { echo "FAIL: the summary does not count the requests answered after a retry"; exit 1; }
wait_ms=$(grep -oE "longest wait [0-9]+ ms" "$work/out.txt" | grep -oE "[0-9]+")
[ "$wait_ms" -ge 1000 ] || { echo "FAIL: longest wait $wait_ms ms, yet the simulator stopped for 1500 ms"; exit 1; }
exit 0
