#!/usr/bin/env bash
# A rig file made into firmware and run (the qemu part; firmware_build.sh
# built t.toml's images): `conformance --qemu t.toml` against each board's
# HIL image in QEMU must find the image the build made (the cache folder,
# keyed by the rig), not build it again, and pass every check; a scripted
# session reads the file's own defaults back from the image.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   firmware_build_qemu.sh CONSOLE STAGE_FOLDER
set -u
console=$1
stage=$2 part=qemu
. "$(dirname "$0")/rig_image_test_prelude.sh"

printf 'get Q\n' >getq.nls
for board in mps2-an386 stm32f4 mps2-an500; do
  hil=$(grep -- "-bender-hil.elf\$" build-$board.txt | awk '{print $2}')
  [ -f "$hil" ] || { say "$board: no HIL image in build-$board.txt"; continue; }
  before=$(stat -c %Y "$hil")
  timeout 300 "$console" conformance --qemu t.toml --board $board --json >conf.json 2>conf.err ||
    say "conformance --qemu t.toml --board $board: $(cat conf.json conf.err)"
  python3 -c 'import json,sys; j=json.load(open("conf.json")); sys.exit(not (j["target"].startswith("qemu bender") and j["failed"] == 0 and j["passed"] > 0))' ||
    say "$board: conformance: $(head -c 300 conf.json)"
  # The image serves the file's own defaults, not tendon's.
  timeout 120 "$console" --qemu t.toml --board $board --no-record --script getq.nls >getq.txt 2>&1 ||
    say "--qemu t.toml --board $board --script: $(tail -5 getq.txt)"
  grep -qE "^Q = 0.001 4000 3000( |$)" getq.txt || say "$board: the image does not serve t.toml's Q: $(cat getq.txt)"
  [ "$(stat -c %Y "$hil")" = "$before" ] || say "$board: conformance built the image again"
done

[ $fail -eq 0 ] && echo "firmware build from a rig file: all checks passed"
exit $fail
