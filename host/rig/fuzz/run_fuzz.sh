#!/usr/bin/env bash
# Runs the rig-file fuzz target (fuzz_rig_file.cpp) for a bounded time, its
# corpus seeded with the shipped rig files and the example's. What a run
# finds is kept under OUT (crash-*, timeout-*, oom-*: each becomes a case of
# tests/host/rig/test_rig_loader.cpp) and fails the script.
#   run_fuzz.sh BUILD_DIR SECONDS [OUT]
# BUILD_DIR: a clang build with NLSOFT_FUZZ=ON (cmake/dev sanitize makes one).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
build=$1 seconds=$2
out=${3:-$build/fuzz-out}
target=$build/host/rig/fuzz/nlsoft-fuzz-rig-file
mkdir -p "$out/rig-file" "$out/seeds-rig-file"
cp "$root"/rigs/*.toml "$root"/rigs/examples/*.toml "$out/seeds-rig-file/"

echo "fuzz: nlsoft-fuzz-rig-file for ${seconds} s" >&2
# -max_len: the largest shipped file is 7.7 kB; -timeout: a file that makes
# the loader loop is a finding, not a slow input.
status=0
if ! "$target" -max_total_time="$seconds" -max_len=16384 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$out/rig-file-" "$out/rig-file" "$out/seeds-rig-file" 2>"$out/rig-file.log"; then
  status=1
  echo "fuzz: nlsoft-fuzz-rig-file FOUND A FAULT: see $out/rig-file.log and $out/rig-file-*" >&2
fi
grep -E '^stat::number_of_executed_units|^stat::average_exec_per_sec|^#[0-9]+ *DONE' "$out/rig-file.log" >&2 || true
exit $status
