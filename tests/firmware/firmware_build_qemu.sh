#!/usr/bin/env bash
# A rig file made into firmware and run, as a lab would: tendon's rig under
# another name, at another rate and tuning (t.toml), built with
# `nlsoft-console firmware build --rig t.toml` for both boards, then
# `conformance --qemu t.toml` against each board's HIL image in QEMU, which
# must find the image the build made (the cache folder, keyed by the rig)
# and pass every check. Each image is built once per run.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   firmware_build_qemu.sh CONSOLE SOURCE_DIR
set -u
console=$1 src=$2
command -v arm-none-eabi-g++ >/dev/null || { echo "SKIP: arm-none-eabi-g++ is not installed"; exit 77; }
command -v qemu-system-arm >/dev/null || { echo "SKIP: qemu-system-arm is not installed"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
export XDG_CACHE_HOME=$work/cache
unset NLSOFT_M4_IMAGE
fail=0

sed -e 's/^name = "tendon"/name = "bender"/' -e 's/^rate_hz = 120.0/rate_hz = 100.0/' \
    -e 's/^Q = \[1e-3, 5e3, 2e3\]/Q = [1e-3, 4e3, 3e3]/' -e 's/^eps = .*/eps = 0.01/' "$src/rigs/tendon.toml" >t.toml
grep -q '^rate_hz = 100.0' t.toml && grep -q '^Q = \[1e-3, 4e3, 3e3\]' t.toml || { echo "FAIL: t.toml not edited"; exit 1; }

printf 'get Q\n' >getq.nls
for board in mps2-an386 stm32f4; do
  prefix=nlsoft-m4
  [ $board = stm32f4 ] && prefix=nlsoft-stm32f4
  if ! "$console" firmware build --rig t.toml --board $board >build.txt 2>build.err; then
    echo "FAIL: firmware build --board $board: $(cat build.txt build.err)"
    fail=1
    continue
  fi
  for image in "$prefix-bender.elf" "$prefix-bender-hil.elf"; do
    grep -q "/$image\$" build.txt || { echo "FAIL: $board: $image not reported: $(cat build.txt)"; fail=1; }
  done
  [ "$(grep -cE '^ +flash [0-9]+ bytes, RAM [0-9]+ bytes$' build.txt)" = 2 ] ||
    { echo "FAIL: $board: no sizes: $(cat build.txt)"; fail=1; }
  hil=$(grep -- "-bender-hil.elf\$" build.txt | awk '{print $2}')
  [ -f "$hil" ] || { echo "FAIL: $board: $hil is not there"; fail=1; }
  before=$(stat -c %Y "$hil")
  if ! timeout 300 "$console" conformance --qemu t.toml --board $board --json >conf.json 2>conf.err; then
    echo "FAIL: conformance --qemu t.toml --board $board: $(cat conf.json conf.err)"
    fail=1
  fi
  python3 -c 'import json,sys; j=json.load(open("conf.json")); sys.exit(not (j["target"].startswith("qemu bender") and j["failed"] == 0 and j["passed"] > 0))' ||
    { echo "FAIL: $board: conformance: $(head -c 300 conf.json)"; fail=1; }
  # The image serves the file's own defaults, not tendon's.
  if ! timeout 120 "$console" --qemu t.toml --board $board --no-record --script getq.nls >getq.txt 2>&1; then
    echo "FAIL: --qemu t.toml --board $board --script: $(tail -5 getq.txt)"
    fail=1
  fi
  grep -qE "^Q = 0.001 4000 3000( |$)" getq.txt || { echo "FAIL: $board: the image does not serve t.toml's Q: $(cat getq.txt)"; fail=1; }
  [ "$(stat -c %Y "$hil")" = "$before" ] || { echo "FAIL: $board: conformance built the image again"; fail=1; }
done

[ $fail -eq 0 ] && echo "firmware build from a rig file: all checks passed"
exit $fail
