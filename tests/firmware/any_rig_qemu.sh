#!/usr/bin/env bash
# A rig that exists only as a file, on the MCU (the qemu part; the images,
# the trained model and other.nlsm come from any_rig_build.sh): for each
# board QEMU boots the HIL image built from my.toml for `conformance --qemu
# my.toml` (every check passes, on the image just built) and for a scripted
# `--qemu my.toml` session that records runs with no lost frame. Last, a
# model of another shape is refused before a byte is sent: the firmware
# still runs the trained model afterwards (a run on the same QEMU carries
# its hash).
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   any_rig_qemu.sh CONSOLE STAGE_FOLDER
set -u
console=$1
stage=$2 part=qemu
. "$(dirname "$0")/rig_image_test_prelude.sh"

hash=$("$console" model info trained.nlsm | sed -n 's/^ *hash 0x\([0-9a-f]*\)$/\1/p')
[ -n "$hash" ] || { echo "FAIL: no hash from model info"; exit 1; }
for board in mps2-an386 stm32f4; do
  prefix=nlsoft-m4
  [ $board = stm32f4 ] && prefix=nlsoft-stm32f4
  hil=$(grep -- "/$prefix-stage-hil.elf\$" build-$board.txt | awk '{print $2}')
  [ -f "$hil" ] || { say "$board: no HIL image in build-$board.txt: $(cat build-$board.txt)"; continue; }
  before=$(stat -c %Y "$hil")

  timeout 300 "$console" conformance --qemu my.toml --board $board --json >conf.json 2>log.txt ||
    say "conformance --qemu my.toml --board $board: $(head -c 600 conf.json) $(tail -3 log.txt)"
  [ "$(json conf.json 'j["target"].startswith("qemu stage") and j["failed"] == 0 and j["passed"] > 70')" = True ] ||
    say "$board: conformance: $(head -c 300 conf.json)"

  # Runs on the MCU's own controller, the trained model embedded.
  printf 'run 3s label=%s-1\nexpect lost_frames == 0\nrun 3s label=%s-2\nexpect lost_frames == 0\n' $board $board >hil.nls
  timeout 120 "$console" --qemu my.toml --board $board --script hil.nls >session.txt 2>&1 ||
    say "--qemu my.toml --board $board --script: $(tail -5 session.txt)"
  for run in $board-1 $board-2; do
    [ -n "$(recorded $run 200 "$hash")" ] || say "$board: run $run not recorded in full: $(cat session.txt)"
  done
  [ "$(stat -c %Y "$hil")" = "$before" ] || say "$board: --qemu built the image again"
  [ $board = mps2-an386 ] && an386=$hil
done

# A model of another shape, on the QEMU image a user started by hand (so
# that the firmware outlives the console): refused from RIG_INFO before the
# transfer, in one sentence, exit 2; the next session's run on the same
# firmware still runs the trained model.
if [ -f "${an386:-}" ]; then
  boot_qemu mps2-an386 "$an386"
  echo "model upload other.nlsm" >other.nls
  timeout 60 "$console" "$port" --rig my.toml --script other.nls >other.txt 2>&1
  rc=$?
  cat other.txt
  [ $rc -eq 2 ] || say "another shape: exit $rc, expected 2"
  # The image's shape is the trained model's, whichever candidate train kept.
  shape=$("$console" model info trained.nlsm | awk '$2 == "Dense" { s = s ? s "->" $5 : "Dense " $3 "->" $5 } END { print s }')
  grep -qF "other.nlsm is Dense 15->8->2; this firmware (rig stage) accepts $shape only" other.txt ||
    say "another shape: not refused by its shape: $(cat other.txt)"
  grep -q "in force" other.txt && say "another shape: a model was put in force"
  printf 'run 1s label=after-refusal\n' >after.nls
  timeout 60 "$console" "$port" --rig my.toml --script after.nls >after.txt 2>&1 || say "after the refusal: $(tail -5 after.txt)"
  [ -n "$(recorded after-refusal 40 "$hash")" ] ||
    say "after the refusal the firmware does not run the trained model: $(cat after.txt)"
  kill "$qemu"
  wait "$qemu" 2>/dev/null
fi

[ $fail -eq 0 ] && echo "a rig file from simulation to both boards' HIL images: all checks passed"
exit $fail
