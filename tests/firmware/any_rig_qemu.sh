#!/usr/bin/env bash
# A rig that exists only as a file, from simulation to the MCU, as a lab
# would take it: my.toml (tests/app/rig/stage.toml, not one of rigs/: 3 inputs, 2
# outputs, 5 sensors, 80 Hz, a generic plant) is recorded from its plant and
# trained (`dataset --rig`, `train --rig`); the model tracks an Infinity on
# that plant (`simulate --rig --model`, nRMSE <= 5 % of the output span);
# the simulator serves the file with the model (`--sim my.toml` records a
# run; `conformance --sim my.toml --model`). Then for each board
# `firmware build --rig my.toml --hil --model` builds the image that
# simulates the rig on the MCU; QEMU boots it for `conformance --qemu
# my.toml` (every check passes, on the image just built) and for a scripted
# `--qemu my.toml` session that records runs with no lost frame. Last, a
# model of another shape is refused before a byte is sent: the firmware
# still runs the trained model afterwards (a run on the same QEMU carries
# its hash).
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   any_rig_qemu.sh CONSOLE RIG_FILE
set -u
console=$1
fixture=$2  # tests/app/rig/stage.toml
. "$(dirname "$0")/rig_image_test_prelude.sh"
# recorded LABEL MIN_SAMPLES: the id of the run of that label, recorded in full
# with at least MIN_SAMPLES samples and no frame lost, whose firmware ran the
# trained model (`runs show`: "model <hash>"); nothing otherwise.
recorded() {
  "$console" runs list --json >runs.json 2>log.txt || { say "runs list: $(cat log.txt)"; return; }
  local id
  id=$(json runs.json "' '.join(str(r['id']) for r in j if r['label'] == '$1' and r['end_reason'] == 'completed' and r['samples'] >= $2 and r['lost_frames'] == 0)")
  [ -n "$id" ] && "$console" runs show "$id" | grep -q ", model $hash, " && echo "$id"
}

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
[ -n "$(recorded sim 80)" ] || say "--sim my.toml: no run recorded: $(cat session.txt)"
timeout 120 "$console" conformance --sim my.toml --model trained.nlsm --json >conf.json 2>log.txt ||
  say "conformance --sim my.toml: $(head -c 600 conf.json) $(cat log.txt)"
[ "$(json conf.json 'j["target"] == "sim stage" and j["failed"] == 0 and j["passed"] > 70')" = True ] ||
  say "conformance --sim: $(head -c 300 conf.json)"

# Another shape: a model the images have no kernel for.
"$console" train --rig my.toml --data my.csv --out other.nlsm --hidden 8 --epochs 1 >log.txt 2>&1 ||
  { cat log.txt; echo "FAIL: train other.nlsm"; exit 1; }
for board in mps2-an386 stm32f4; do
  prefix=nlsoft-m4
  [ $board = stm32f4 ] && prefix=nlsoft-stm32f4
  if ! "$console" firmware build --rig my.toml --board $board --hil --model trained.nlsm >build.txt 2>build.err; then
    say "firmware build --board $board: $(cat build.txt build.err)"
    continue
  fi
  cat build.txt
  hil=$(grep -- "/$prefix-stage-hil.elf\$" build.txt | awk '{print $2}')
  [ -f "$hil" ] || { say "$board: no HIL image reported: $(cat build.txt)"; continue; }
  grep -qE '^ +flash [0-9]+ bytes, RAM [0-9]+ bytes$' build.txt || say "$board: no sizes: $(cat build.txt)"
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
    [ -n "$(recorded $run 200)" ] || say "$board: run $run not recorded in full: $(cat session.txt)"
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
  grep -qF "other.nlsm is Dense 15->8->2; this firmware (rig stage) accepts Dense 15->16->2 only" other.txt ||
    say "another shape: not refused by its shape: $(cat other.txt)"
  grep -q "in force" other.txt && say "another shape: a model was put in force"
  printf 'run 1s label=after-refusal\n' >after.nls
  timeout 60 "$console" "$port" --rig my.toml --script after.nls >after.txt 2>&1 || say "after the refusal: $(tail -5 after.txt)"
  [ -n "$(recorded after-refusal 40)" ] ||
    say "after the refusal the firmware does not run the trained model: $(cat after.txt)"
  kill "$qemu"
  wait "$qemu" 2>/dev/null
fi

[ $fail -eq 0 ] && echo "a rig file from simulation to both boards' HIL images: all checks passed"
exit $fail
