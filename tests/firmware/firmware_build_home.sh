#!/usr/bin/env bash
# `firmware build` without --out keeps its images under the cache folder of
# an existing absolute HOME (or XDG_CACHE_HOME) and creates no folder
# anywhere else: HOME=/nonexistent made /nonexistent/.cache/... at the
# root, a relative HOME a folder in the current one. Each is refused with
# the variable named, before anything is built.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ (the build checks its
# tools first).
#   firmware_build_home.sh CONSOLE SOURCE_DIR WORK_FOLDER
set -u
console=$1 src=$2 work=$3
command -v arm-none-eabi-g++ >/dev/null || { echo "SKIP: arm-none-eabi-g++ is not installed"; exit 77; }
rm -rf "$work" && mkdir -p "$work/cwd" || exit 1
cd "$work/cwd" || exit 1
fail=0
say() { echo "FAIL: $*"; fail=1; }
build=(timeout 600 "$console" firmware build --rig "$src/rigs/msd.toml" --board mps2-an386 --hil)

out=$(env -u XDG_CACHE_HOME HOME="$work/missing" "${build[@]}" 2>&1)
[ $? -ne 0 ] || say "HOME=$work/missing: built: $out"
grep -qF "no folder for the image cache: HOME=$work/missing does not exist" <<<"$out" || say "HOME missing: $out"
[ -e "$work/missing" ] && say "HOME=$work/missing was created"

out=$(env -u XDG_CACHE_HOME HOME=rel "${build[@]}" 2>&1)
[ $? -ne 0 ] || say "HOME=rel: built: $out"
grep -qF "HOME=rel is not an absolute path" <<<"$out" || say "HOME relative: $out"
[ -e "$work/cwd/rel" ] && say "HOME=rel made $work/cwd/rel"

out=$(HOME="$work" XDG_CACHE_HOME="$work/nowhere/cache" "${build[@]}" 2>&1)
[ $? -ne 0 ] || say "XDG_CACHE_HOME missing: built: $out"
grep -qF "XDG_CACHE_HOME=$work/nowhere/cache does not exist" <<<"$out" || say "XDG_CACHE_HOME missing: $out"
[ -e "$work/nowhere" ] && say "XDG_CACHE_HOME=$work/nowhere/cache: $work/nowhere was created"
[ -z "$(ls -A "$work/cwd")" ] || say "the current folder holds: $(ls -A "$work/cwd")"
exit $fail
