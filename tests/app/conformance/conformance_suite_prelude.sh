# Sourced by the conformance fault tests (conformance_*.sh), after
# console=CONSOLE: a private $work folder, removed at exit; start_suite ARGS
# runs `$console conformance --sim msd ARGS` in the background, its output
# in $work/out.txt, and returns once the ping check has passed (the link is
# up and the suite under way), with pid = the console, sim = its simulator;
# end_suite RC WHY waits for the suite, prints its output and fails the test
# unless it exited RC.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
start_suite() {
  "$console" conformance --sim msd "$@" >"$work/out.txt" 2>&1 &
  pid=$!
  for _ in $(seq 1500); do grep -q "^PASS ping" "$work/out.txt" && break; sleep 0.02; done
  sim=$(pgrep -P $pid -f nlsoft-firmware-sim)
  [ -n "$sim" ] || { echo "FAIL: no simulator under the console"; cat "$work/out.txt"; kill $pid; exit 1; }
}
end_suite() {
  wait $pid
  local rc=$?
  cat "$work/out.txt"
  [ $rc -eq "$1" ] || { echo "FAIL: exit $rc, expected $1 ($2)"; exit 1; }
}
