#!/usr/bin/env bash
# Runs the recording database readers' fuzz target (fuzz_run_store.cpp) for
# a bounded time, its corpus seeded with databases the console's schema
# makes (the target writes them: -make_seeds). What a run finds is kept
# under OUT (crash-*, timeout-*, oom-* files: each becomes a regression
# test in tests/app/record/test_crafted_db.cpp) and fails the script.
#   run_fuzz.sh BUILD_DIR SECONDS [OUT]
# BUILD_DIR: a clang build with NLSOFT_FUZZ=ON (cmake/dev sanitize makes one).
set -euo pipefail
build=$1 seconds=$2
out=${3:-$build/fuzz-out}
target=$build/app/record/fuzz/nlsoft-fuzz-run-store
mkdir -p "$out/run-store" "$out/seeds-run-store"
"$target" -make_seeds="$out/seeds-run-store"

echo "fuzz: nlsoft-fuzz-run-store for ${seconds} s" >&2
# -max_len: the seeds are 7-12 kB (512-byte pages); -timeout: a reader that
# loops (a recursive view once did) is a finding, not a slow input.
status=0
if ! "$target" -max_total_time="$seconds" -max_len=16384 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$out/run-store-" "$out/run-store" "$out/seeds-run-store" 2>"$out/run-store.log"; then
  status=1
  echo "fuzz: nlsoft-fuzz-run-store FOUND A FAULT: see $out/run-store.log and $out/run-store-*" >&2
fi
grep -E '^stat::number_of_executed_units|^stat::average_exec_per_sec|^#[0-9]+ *DONE' "$out/run-store.log" >&2 || true
exit $status
