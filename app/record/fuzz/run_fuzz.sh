#!/usr/bin/env bash
# Runs the recording database readers' fuzz target (fuzz_run_store.cpp) for
# a bounded time, its corpus seeded with databases the console's schema
# makes (the target writes them: -make_seeds). What a run finds is kept
# under OUT (crash-*, timeout-*, oom-* files: each becomes a regression
# test in tests/app/record/test_crafted_db.cpp) and fails the script.
#   run_fuzz.sh BUILD_DIR SECONDS [OUT]
# BUILD_DIR: a clang build with NLSOFT_FUZZ=ON (cmake/dev sanitize makes one).
set -euo pipefail
. "$(cd "$(dirname "$0")/../../.." && pwd)/cmake/fuzz_run.sh"
target=app/record/fuzz/nlsoft-fuzz-run-store
mkdir -p "$out/seeds-run-store"
"$build/$target" -make_seeds="$out/seeds-run-store"

# -max_len: the seeds are 7-12 kB (512-byte pages); -timeout: a reader that
# loops (a recursive view once did) is a finding, not a slow input.
fuzz_run "$build" "$out" "$seconds" "$target" run-store "$out/seeds-run-store" -max_len=16384 -timeout=10
exit $fuzz_status
