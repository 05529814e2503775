#!/usr/bin/env bash
# The conformance suite when another program reads the port too (here `cat`
# on the console's pseudo-terminal, started just after the ping check): the
# replies go to that program, and the link error names it by pid and name.
#   conformance_second_reader.sh CONSOLE
set -u
console=$1
thief=""
cleanup() {
  [ -n "$thief" ] && kill "$thief" 2>/dev/null
  rm -rf "$work"
}
. "$(dirname "$0")/conformance_suite_prelude.sh"
trap cleanup EXIT  # after the prelude's own trap, which it replaces
start_suite --timeout 200
port=$(for f in /proc/$pid/fd/*; do readlink "$f"; done | grep -m1 '^/dev/pts/')
[ -n "$port" ] || { echo "FAIL: the console holds no pseudo-terminal"; kill $pid; exit 1; }
cat "$port" >/dev/null 2>&1 &
thief=$!
end_suite 2 "a link error"
grep -qE "^link error: no reply to .*; PID $thief \(cat\) also has $port open" "$work/out.txt" ||
  { echo "FAIL: the error does not name the second reader (PID $thief, cat)"; exit 1; }
exit 0
