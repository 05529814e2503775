# Sourced by the fuzz scripts (app/link/fuzz, app/record/fuzz, app/model/fuzz,
# host/rig/fuzz/run_fuzz.sh), whose arguments are BUILD_DIR SECONDS [OUT]:
# it sets build, seconds, out (default BUILD_DIR/fuzz-out) and root (the
# repository) from them, and gives one libFuzzer target run for a bounded time:
#   fuzz_run BUILD OUT SECONDS TARGET NAME SEEDS [libFuzzer options...]
# TARGET is its path under BUILD; the corpus grows in OUT/NAME, what it
# finds is kept as OUT/NAME-crash-* (timeout-*, oom-*) with its log in
# OUT/NAME.log, and fuzz_status becomes 1. The run's figures go to stderr.
# -rss_limit_mb: the recorder's queue and SQLite's cache stay well under it.
build=${1:?give BUILD_DIR SECONDS [OUT]} seconds=${2:?give BUILD_DIR SECONDS [OUT]}
out=${3:-$build/fuzz-out}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
fuzz_status=0
fuzz_run() {
  local build=$1 out=$2 seconds=$3 target=$4 name=$5 seeds=$6
  shift 6
  mkdir -p "$out/$name"
  echo "fuzz: $target for ${seconds} s" >&2
  if ! "$build/$target" -max_total_time="$seconds" -rss_limit_mb=2048 -print_final_stats=1 "$@" \
      -artifact_prefix="$out/$name-" "$out/$name" "$seeds" 2>"$out/$name.log"; then
    fuzz_status=1
    echo "fuzz: $target FOUND A FAULT: see $out/$name.log and $out/$name-*" >&2
  fi
  grep -E '^stat::number_of_executed_units|^stat::average_exec_per_sec|^#[0-9]+ *DONE' "$out/$name.log" >&2 || true
}
