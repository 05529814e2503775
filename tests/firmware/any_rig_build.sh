#!/usr/bin/env bash
# A rig that exists only as a file, from simulation to the MCU, as a lab
# would take it (the build part; any_rig_qemu.sh boots what it builds):
# my.toml (tests/app/rig/stage.toml, not one of rigs/: 3 inputs, 2 outputs,
# 5 sensors, 80 Hz, a generic plant) is recorded from its plant and trained
# (`dataset --rig`, `train --rig`); the model tracks an Infinity on that
# plant (`simulate --rig --model`, nRMSE <= 5 % of the output span); the
# simulator serves the file with the model (`--sim my.toml` records a run;
# `conformance --sim my.toml --model`). Then for each board `firmware build
# --rig my.toml --hil --model` builds the image that simulates the rig on
# the MCU, with its sizes; and other.nlsm, a model of another shape, is
# trained for the qemu part to upload.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   any_rig_build.sh CONSOLE RIG_FILE STAGE_FOLDER
set -u
console=$1
fixture=$2  # tests/app/rig/stage.toml
stage=$3 part=build
. "$(dirname "$0")/rig_image_test_prelude.sh"

cp "$fixture" my.toml || exit 1

# Recorded from the plant and trained: as few samples and epochs as still track well.
"$console" dataset --rig my.toml --out my.csv --steps 12000 >log.txt 2>&1 || { cat log.txt; echo "FAIL: dataset"; exit 1; }
"$console" train --rig my.toml --data my.csv --out trained.nlsm --epochs 60 >log.txt 2>&1 ||
  { cat log.txt; echo "FAIL: train"; exit 1; }
"$console" simulate --rig my.toml --model trained.nlsm --reference infinity --json >sim.json 2>log.txt ||
  { cat log.txt; echo "FAIL: simulate"; exit 1; }
# nRMSE against the output span (20 mm), the worst axis.
worst=$(json sim.json 'max(e / 20.0 for e in j["rmse"])')
echo "simulate: Infinity tracked at nRMSE $worst of the output span (nrmse $(json sim.json 'j["nrmse"]'))"
python3 -c "import sys; sys.exit(not (0 < $worst <= 0.05))" || say "simulate: nRMSE $worst of the span, above 5 %"
hash=$("$console" model info trained.nlsm | sed -n 's/^ *hash 0x\([0-9a-f]*\)$/\1/p')
[ -n "$hash" ] || { echo "FAIL: no hash from model info"; exit 1; }

# The simulator serves the file, with the trained model uploaded.
printf 'model upload trained.nlsm\nrun 1s label=sim\nexpect lost_frames == 0\n' >sim.nls
timeout 120 "$console" --sim my.toml --sim-fast --script sim.nls >session.txt 2>&1 ||
  say "--sim my.toml --script: $(tail -5 session.txt)"
grep -q "model trained.nlsm in force: hash $hash confirmed" session.txt || say "--sim: no model confirmed: $(cat session.txt)"
[ -n "$(recorded sim 80 "$hash")" ] || say "--sim my.toml: no run recorded: $(cat session.txt)"
timeout 120 "$console" conformance --sim my.toml --model trained.nlsm --json >conf.json 2>log.txt ||
  say "conformance --sim my.toml: $(head -c 600 conf.json) $(cat log.txt)"
[ "$(json conf.json 'j["target"] == "sim stage" and j["failed"] == 0 and j["passed"] > 70')" = True ] ||
  say "conformance --sim: $(head -c 300 conf.json)"

# Another shape: a model the images have no kernel for.
"$console" train --rig my.toml --data my.csv --out other.nlsm --hidden 8 --epochs 1 >log.txt 2>&1 ||
  { cat log.txt; echo "FAIL: train other.nlsm"; exit 1; }

# Each board's HIL image with the trained model; build-BOARD.txt names it.
for board in mps2-an386 stm32f4; do
  prefix=nlsoft-m4
  [ $board = stm32f4 ] && prefix=nlsoft-stm32f4
  if ! "$console" firmware build --rig my.toml --board $board --hil --model trained.nlsm >build-$board.txt 2>build.err; then
    say "firmware build --board $board: $(cat build-$board.txt build.err)"
    continue
  fi
  cat build-$board.txt
  hil=$(grep -- "/$prefix-stage-hil.elf\$" build-$board.txt | awk '{print $2}')
  [ -f "$hil" ] || say "$board: no HIL image reported: $(cat build-$board.txt)"
  grep -qE '^ +flash [0-9]+ bytes, RAM [0-9]+ bytes$' build-$board.txt || say "$board: no sizes: $(cat build-$board.txt)"
done
built
