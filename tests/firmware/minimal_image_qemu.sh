#!/usr/bin/env bash
# The images of minimal_image_build.sh in QEMU: `conformance --qemu
# msd-min.toml` on each board passes every check, the services the rig
# file leaves out reported left out (refused `unsupported`), not failed,
# and the minimum's closed-loop run with telemetry passes as on a full image;
# on the small part (mps2-an385) hasel's minimum too, and a closed-loop run
# of it.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   minimal_image_qemu.sh CONSOLE STAGE_FOLDER
set -u
console=$1
stage=$2 part=qemu
. "$(dirname "$0")/rig_image_test_prelude.sh"

for board in mps2-an386 stm32f4 mps2-an385; do
  timeout 300 "$console" conformance --qemu msd-min.toml --board $board --json >conf-$board.json 2>log.txt ||
    say "conformance --qemu msd-min.toml --board $board: $(head -c 600 conf-$board.json) $(tail -3 log.txt)"
  [ "$(json conf-$board.json 'j["target"].startswith("qemu msd-min") and j["failed"] == 0 and j["passed"] > 60')" = True ] ||
    say "$board: conformance: $(head -c 300 conf-$board.json)"
  for check in xfer_model_left_out xfer_table_left_out ident_left_out telemetry run_start; do
    [ "$(json conf-$board.json "any(c['name'] == '$check' and c['pass'] for c in j['checks'])")" = True ] ||
      say "$board: no passing check $check: $(head -c 300 conf-$board.json)"
  done
done
# hasel's minimum on the small part, in closed loop with the controller in
# soft float: every planned step of a 2 s run at 130 Hz recorded, none lost.
timeout 300 "$console" conformance --qemu hasel-min.toml --board mps2-an385 --json >conf-m3-hasel.json 2>log.txt ||
  say "conformance --qemu hasel-min.toml --board mps2-an385: $(head -c 600 conf-m3-hasel.json) $(tail -3 log.txt)"
[ "$(json conf-m3-hasel.json 'j["failed"] == 0 and j["passed"] > 60')" = True ] ||
  say "mps2-an385 hasel: conformance: $(head -c 300 conf-m3-hasel.json)"
cat >m3-run.nls <<'NLS'
run 2s label=m3
expect lost == 0
expect samples == 260
NLS
timeout 300 "$console" --qemu hasel-min.toml --board mps2-an385 --script m3-run.nls --db m3.db >m3-run.txt 2>&1 ||
  say "a closed-loop run of hasel's minimum on mps2-an385: $(tail -8 m3-run.txt)"
cat m3-run.txt
exit $fail
