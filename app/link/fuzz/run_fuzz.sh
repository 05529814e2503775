#!/usr/bin/env bash
# Runs the protocol decoder's and the console intake's fuzz targets for a
# bounded time each, the corpus seeded from the golden vectors'
# frames (protocol/fuzz/corpus). What a run finds is kept under OUT (crash-*
# files: each becomes a regression test) and fails the script.
#   run_fuzz.sh BUILD_DIR SECONDS_PER_TARGET [OUT]
# BUILD_DIR: a clang build with NLSOFT_FUZZ=ON (cmake/dev sanitize makes one).
set -euo pipefail
. "$(cd "$(dirname "$0")/../../.." && pwd)/cmake/fuzz_run.sh"
mkdir -p "$out/seeds-intake"

# The intake's input is two bytes (which INFO, run or not and chunk size)
# and the line: each golden frame as a msd-shaped and a hasel-shaped
# firmware sends it, recorded and not, and all of them in one line.
: >"$out/seeds-intake/all"
for f in "$root"/protocol/fuzz/corpus/*; do
  name=$(basename "$f")
  for prefix in '\000\077' '\001\277' '\360\201'; do
    { printf "$prefix"; tail -c +2 "$f"; } >"$out/seeds-intake/$name-$(printf '%s' "$prefix" | tr -dc 0-9)"
  done
  tail -c +2 "$f" >>"$out/seeds-intake/all.body"
done
{ printf '\001\277'; cat "$out/seeds-intake/all.body"; } >"$out/seeds-intake/all"
rm -f "$out/seeds-intake/all.body"

fuzz_run "$build" "$out" "$seconds" protocol/fuzz/nlsoft-fuzz-decoder decoder "$root/protocol/fuzz/corpus"
fuzz_run "$build" "$out" "$seconds" app/link/fuzz/nlsoft-fuzz-intake intake "$out/seeds-intake"
exit $fuzz_status
