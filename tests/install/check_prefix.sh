#!/usr/bin/env bash
# Runs the console from an installed prefix with the build tree out of
# reach: no environment variable, nothing of the build or source folder on
# PATH, and no path of them in the binaries (--no-build-paths: a path
# compiled in would still be there to find while the tests run). Used by the
# `cmake --install` test and the .deb test.
#   check_prefix.sh PREFIX SOURCE_DIR BUILD_DIR VERSION [--images] [--man] [--no-build-paths]
set -euo pipefail
fail() { echo "FAIL: $*" >&2; exit 1; }
prefix=$1 src=$2 build=$3 version=$4
shift 4
images=0 man=0 paths=0
for a in "$@"; do
  case $a in
    --images) images=1 ;;
    --man) man=1 ;;
    --no-build-paths) paths=1 ;;
    *) fail "unknown flag $a" ;;
  esac
done
here=$(cd "$(dirname "$0")" && pwd)

console=$prefix/bin/nlsoft-console
sim=$prefix/libexec/nlsoft/nlsoft-firmware-sim
for f in "$console" "$sim" "$prefix/share/nlsoft/models/hasel.nlsm" "$prefix/share/nlsoft/rigs/hasel.toml" \
  "$prefix/share/nlsoft/rigs/examples/lab-arm.toml" \
  "$prefix/share/doc/nlsoft/README.md" \
  "$prefix/share/doc/nlsoft/CONSOLE.md" "$prefix/share/doc/nlsoft/PROTOCOL.md" \
  "$prefix/share/bash-completion/completions/nlsoft-console"; do
  [ -e "$f" ] || fail "not installed: $f"
done
[ $man = 0 ] || [ -s "$prefix/share/man/man1/nlsoft-console.1" ] || fail "no man page in $prefix/share/man/man1"
if [ $images = 1 ]; then
  # hasel's and tendon's board images are stm32f4's (chips on SPI2, servos on USART1); mps2-an386 and
  # mps2-an500 run their HIL images.
  for rel in m4/nlsoft-m4-hasel-hil.elf m4/nlsoft-m4-msd.elf m7/nlsoft-m7-hasel-hil.elf m7/nlsoft-m7-msd.elf \
    stm32f4/nlsoft-stm32f4-tendon.elf stm32f4/nlsoft-stm32f4-hasel-hil.elf \
    stm32f4/nlsoft-stm32f4-hasel.elf stm32f4/nlsoft-stm32f4-hasel.bin; do
    [ -s "$prefix/share/nlsoft/firmware/$rel" ] || fail "image not installed: share/nlsoft/firmware/$rel"
  done
fi

if [ $paths = 1 ]; then
  for f in "$console" "$sim"; do
    for d in "$src" "$build"; do
      if strings "$f" | grep -F -- "$d"; then fail "$f holds the path $d"; fi
    done
  done
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/home"
# What a user's shell would have: the system's folders, no NLSOFT_*.
run() { env -i HOME="$work/home" PATH=/usr/bin:/bin LANG=C.UTF-8 "$@"; }

out=$(run "$console" --version)
[[ $out == "nlsoft-console $version,"* ]] || fail "--version says '$out', the project is $version"
out=$(run timeout 60 "$console" --sim hasel --no-record --script "$here/session.nls" 2>&1) ||
  fail "--sim hasel session from $prefix: $out"
echo "$out"
out=$(run timeout 60 "$console" simulate --rig hasel --steps 50 2>&1) || fail "simulate from $prefix: $out"
if [ $images = 1 ] && [ -x /usr/bin/qemu-system-arm ]; then
  out=$(run timeout 60 "$console" --qemu hasel --no-record --script "$here/connect.nls" 2>&1) ||
    fail "--qemu hasel session from $prefix: $out"
  echo "$out"
fi
# An image built from a rig file with the prefix's own copy of the firmware sources.
if [ $images = 1 ] && [ -x /usr/bin/arm-none-eabi-g++ ]; then
  out=$(run timeout 600 "$console" firmware build --rig msd --board mps2-an386 --out "$work/fw" 2>&1) ||
    fail "firmware build from $prefix: $out"
  [ -s "$work/fw/nlsoft-m4-msd-hil.elf" ] || fail "firmware build from $prefix made no HIL image: $out"
  grep -qxF "CMAKE_HOME_DIRECTORY:INTERNAL=$prefix/share/nlsoft/firmware-src/firmware/ports/mps2-an386" \
    "$work/fw/.build/CMakeCache.txt" || fail "firmware build from $prefix did not use its firmware-src: $out"
  echo "$out"
fi

# Without the simulator the error names every place looked at.
mv "$sim" "$work/sim"
out=$(run "$console" --sim hasel --no-record --script "$here/session.nls" 2>&1) && fail "ran without the simulator"
mv "$work/sim" "$sim"
echo "$out" | grep -qF "$prefix/libexec/nlsoft/nlsoft-firmware-sim" || fail "the error does not name libexec: $out"
echo "$out" | grep -q "PATH" || fail "the error does not name PATH: $out"
echo "ok: $prefix works on its own"
