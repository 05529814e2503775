#!/usr/bin/env bash
# A firmware built without a service (the rig file's [firmware] features,
# PROTOCOL.md 9.12), through the real console against the simulator that
# serves such a file: each request of a left-out service is refused before
# anything is sent, naming the service and the rig file's word for it, and
# the minimum (a run) still works.
#   left_out_services.sh CONSOLE SOURCE_DIR
set -u
console=$1 src=$2
fail=0
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
export XDG_DATA_HOME=$work/data
say() { echo "FAIL: $*"; fail=1; }
sed 's/^name = "msd"/name = "msd-min"/' "$src/rigs/msd.toml" >msd-min.toml
printf '\n[firmware]\nfeatures = []\n' >>msd-min.toml
printf 'y\n0.1\n0.2\n0.3\n' >ref.csv

# script WORDS PATTERN: the script fails, saying PATTERN.
script() {
  printf '%b' "$1" >s.nls
  out=$(timeout 60 "$console" --sim msd-min.toml --sim-fast --script s.nls 2>&1)
  rc=$?
  [ $rc -ne 0 ] && grep -qF -- "$2" <<<"$out" || say "script '$1': rc=$rc, not '$2': $out"
}
script 'model upload '"$src"'/app/models/msd.nlsm\n' \
  'was built without model uploads (XFER kind 2): its rig file'"'"'s [firmware] features leave out "model-upload"'
script 'ref load ref.csv\n' \
  'was built without reference-table uploads (XFER kind 1): its rig file'"'"'s [firmware] features leave out "table-upload"'
script 'ident prbs 1s\n' \
  'was built without identification runs (IDENT_START): its rig file'"'"'s [firmware] features leave out "ident"'
script 'settings save\n' 'keeps no settings: it has no SETTINGS capability'

printf 'run 300ms label=minimal\n' >run.nls
timeout 60 "$console" --sim msd-min.toml --sim-fast --script run.nls >run.txt 2>&1 || say "a run on the minimum: $(cat run.txt)"
exit $fail
