#!/usr/bin/env bash
# Runs the rig-file fuzz target (fuzz_rig_file.cpp) for a bounded time, its
# corpus seeded with the shipped rig files and the example's. What a run
# finds is kept under OUT (crash-*, timeout-*, oom-*: each becomes a case of
# tests/host/rig/test_rig_loader.cpp) and fails the script.
#   run_fuzz.sh BUILD_DIR SECONDS [OUT]
# BUILD_DIR: a clang build with NLSOFT_FUZZ=ON (cmake/dev sanitize makes one).
set -euo pipefail
. "$(cd "$(dirname "$0")/../../.." && pwd)/cmake/fuzz_run.sh"
mkdir -p "$out/seeds-rig-file"
cp "$root"/rigs/*.toml "$root"/rigs/examples/*.toml "$out/seeds-rig-file/"

# -max_len: the largest shipped file is 7.7 kB; -timeout: a file that makes
# the loader loop is a finding, not a slow input.
fuzz_run "$build" "$out" "$seconds" host/rig/fuzz/nlsoft-fuzz-rig-file rig-file "$out/seeds-rig-file" \
  -max_len=16384 -timeout=10
exit $fuzz_status
