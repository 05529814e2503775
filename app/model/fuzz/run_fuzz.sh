#!/usr/bin/env bash
# Runs the model files' fuzz target (fuzz_model_files.cpp) for a bounded
# time, its corpus seeded with the shipped models and plant models made of
# them (the target writes those: -make_seeds). What a run finds is kept
# under OUT (crash-*, timeout-*, oom-*: each becomes a case of
# tests/app/model/test_plant_model.cpp) and fails the script.
#   run_fuzz.sh BUILD_DIR SECONDS [OUT]
# BUILD_DIR: a clang build with NLSOFT_FUZZ=ON (cmake/dev sanitize makes one).
set -euo pipefail
. "$(cd "$(dirname "$0")/../../.." && pwd)/cmake/fuzz_run.sh"
target=app/model/fuzz/nlsoft-fuzz-model-files
mkdir -p "$out/seeds-model-files"
cp "$root"/app/models/*.nlsm "$out/seeds-model-files/"
NLSOFT_MODELS=$root/app/models "$build/$target" -make_seeds="$out/seeds-model-files"

# -max_len: the shipped models are 0.1-5 kB, a plant of four parts ~25 kB.
fuzz_run "$build" "$out" "$seconds" "$target" model-files "$out/seeds-model-files" -max_len=32768 -timeout=10
exit $fuzz_status
