#!/usr/bin/env bash
# A fourth shipped rig is one file: a rigs folder holding the shipped rig
# files and tests/app/rig/stage.toml, copied as it is (no other file of the
# product changed), is what NLSOFT_RIGS points at; then `stage` is a rig by
# name as hasel is: `rig list` lists it, its plant is recorded and trained,
# `simulate --rig stage` runs it, the simulator serves it and passes
# conformance, and `firmware build --rig stage` builds both boards' HIL
# images of it.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   fourth_rig.sh CONSOLE SOURCE_ROOT STAGE_FOLDER
set -u
console=$1
root=$2
stage=$3 part=build
. "$(dirname "$0")/rig_image_test_prelude.sh"

mkdir rigs && cp "$root"/rigs/*.toml rigs/ && cp "$root/tests/app/rig/stage.toml" rigs/ || exit 1
export NLSOFT_RIGS=$work/rigs

"$console" rig list >list.txt 2>&1 || say "rig list: $(cat list.txt)"
for name in hasel msd stage tendon; do
  grep -qw "$name" list.txt || say "rig list does not list $name: $(cat list.txt)"
done
"$console" rig check stage >check.txt 2>&1 || say "rig check stage: $(cat check.txt)"

"$console" dataset --rig stage --out stage.csv --steps 4000 >log.txt 2>&1 || { cat log.txt; echo "FAIL: dataset"; exit 1; }
grep -q "4000 samples of stage" log.txt || say "dataset: $(cat log.txt)"
"$console" train --rig stage --data stage.csv --out stage.nlsm --epochs 5 >log.txt 2>&1 ||
  { cat log.txt; echo "FAIL: train"; exit 1; }
grep -q "trained stage model" log.txt || say "train: $(cat log.txt)"
"$console" simulate --rig stage --model stage.nlsm --reference infinity --json >sim.json 2>log.txt ||
  say "simulate --rig stage: $(cat log.txt)"
[ "$(json sim.json 'len(j["rmse"]) == 2 and j["samples"] > 0')" = True ] || say "simulate: $(head -c 300 sim.json)"

timeout 120 "$console" conformance --sim stage --model stage.nlsm --json >conf.json 2>log.txt ||
  say "conformance --sim stage: $(head -c 600 conf.json) $(cat log.txt)"
[ "$(json conf.json 'j["target"] == "sim stage" and j["failed"] == 0 and j["passed"] > 70')" = True ] ||
  say "conformance --sim stage: $(head -c 300 conf.json)"

for board in mps2-an386 stm32f4; do
  prefix=nlsoft-m4
  [ $board = stm32f4 ] && prefix=nlsoft-stm32f4
  if ! "$console" firmware build --rig stage --board $board --hil --model stage.nlsm >build-$board.txt 2>build.err; then
    say "firmware build --rig stage --board $board: $(cat build-$board.txt build.err)"
    continue
  fi
  hil=$(grep -- "/$prefix-stage-hil.elf\$" build-$board.txt | awk '{print $2}')
  [ -f "$hil" ] || say "$board: no HIL image of stage: $(cat build-$board.txt)"
done
built
