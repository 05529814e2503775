#!/usr/bin/env bash
# $NLSOFT_RIGS comes first, it does not replace the shipped rigs (as
# app/CONSOLE.md says): with a folder holding only another rig, the shipped
# rigs are still found by name, `rig list` lists both folders' names, and a
# rig taken from that folder is said, naming the folder, where it is used.
# A copy of a shipped file there is the shipped rig: nothing is said.
#   rigs_env_folder.sh CONSOLE SOURCE_DIR
set -u
console=$1 src=$2
fail=0
say() { echo "FAIL: $*"; fail=1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/rigs" && cp "$src/tests/app/rig/stage.toml" "$work/rigs/" && cp "$src/rigs/msd.toml" "$work/rigs/" || exit 1
export NLSOFT_RIGS=$work/rigs

out=$("$console" rig check hasel 2>&1) || say "rig check hasel with NLSOFT_RIGS set: $out"
grep -qF "NLSOFT_RIGS" <<<"$out" && say "the shipped hasel said as from NLSOFT_RIGS: $out"
out=$("$console" rig check stage 2>&1) || say "rig check stage: $out"
grep -qF "rig 'stage' is $work/rigs/stage.toml, from the folder \$NLSOFT_RIGS names ($work/rigs)" <<<"$out" ||
  say "rig check stage did not say where stage came from: $out"
[ "$(grep -c "NLSOFT_RIGS" <<<"$out")" = 1 ] || say "said more than once: $out"
out=$("$console" rig check msd 2>&1) || say "rig check msd: $out"
grep -qF "NLSOFT_RIGS" <<<"$out" && say "a copy of the shipped msd said as another rig: $out"
names=$("$console" rig list 2>/dev/null | cut -d' ' -f1 | tr '\n' ' ')
[ "$names" = "hasel msd stage tendon " ] || say "rig list: $names"
# Another file under a shipped name there is that rig, and said.
sed 's/^description = .*/description = "my own msd"/' "$src/rigs/msd.toml" >"$work/rigs/msd.toml"
out=$("$console" rig check msd 2>&1) || say "rig check msd (own): $out"
grep -qF "rig 'msd' is $work/rigs/msd.toml, from the folder \$NLSOFT_RIGS names" <<<"$out" ||
  say "the folder's own msd was not said: $out"
grep -qF "my own msd" <<<"$out" || say "the folder's msd was not the one used: $out"
exit $fail
