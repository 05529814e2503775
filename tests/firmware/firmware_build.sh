#!/usr/bin/env bash
# A rig file made into firmware, as a lab would (the build part;
# firmware_build_qemu.sh runs what it builds): tendon's rig under another
# name, at another rate and tuning, without its servos (t.toml), built with `nlsoft-console
# firmware build --rig t.toml` for each board: the board image and the HIL
# image of each, both named and sized in the output (build-BOARD.txt), the
# stm32f4 .bin files too, and the build's progress naming its steps.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   firmware_build.sh CONSOLE SOURCE_DIR STAGE_FOLDER
set -u
console=$1 src=$2
stage=$3 part=build
. "$(dirname "$0")/rig_image_test_prelude.sh"

# Without tendon's Dynamixel servos (its inputs then drive no pin): a rig
# both boards can carry.
python3 - "$src/rigs/tendon.toml" >tendon-no-servos.toml <<'PY'
import sys
skip = False
for line in open(sys.argv[1]):
    if line.startswith("[[device]]"): skip = True
    elif skip and (line.startswith("[") or line.startswith("#")): skip = False
    if skip or line.split("=")[0].strip() in ("servo", "goal_per_unit", "goal_at_neutral"): continue
    sys.stdout.write(line)
PY
sed -e 's/^name = "tendon"/name = "bender"/' -e 's/^rate_hz = 120.0/rate_hz = 100.0/' \
    -e 's/^Q = \[1e-3, 5e3, 2e3\]/Q = [1e-3, 4e3, 3e3]/' -e 's/^eps = .*/eps = 0.01/' tendon-no-servos.toml >t.toml
grep -q '^rate_hz = 100.0' t.toml && grep -q '^Q = \[1e-3, 4e3, 3e3\]' t.toml || { echo "FAIL: t.toml not edited"; exit 1; }

for board in mps2-an386 stm32f4 mps2-an500; do
  prefix=nlsoft-m4
  [ $board = stm32f4 ] && prefix=nlsoft-stm32f4
  [ $board = mps2-an500 ] && prefix=nlsoft-m7
  # On a terminal (script(1) gives it one), as a person runs it: stdout,
  # the images, to build-BOARD.txt; the progress on the terminal, kept in
  # progress-BOARD.txt.
  if ! script -qec "$(printf '%q ' "$console" firmware build --rig t.toml --board $board) >build-$board.txt" \
      progress-$board.txt >/dev/null; then
    say "firmware build --board $board: $(cat build-$board.txt progress-$board.txt)"
    continue
  fi
  cat build-$board.txt
  # The bar says what it does while it builds, not one line for the whole build.
  for step in "configuring (cmake)" "compiling main.cpp" "linking $prefix-bender.elf"; do
    grep -qF "$step" progress-$board.txt || say "$board: the progress never said '$step': $(tr '\r' '\n' <progress-$board.txt | tail -5)"
  done
  for image in "$prefix-bender.elf" "$prefix-bender-hil.elf"; do
    grep -q "/$image\$" build-$board.txt || say "$board: $image not reported: $(cat build-$board.txt)"
  done
  [ "$(grep -cE '^ +flash [0-9]+ bytes, RAM [0-9]+ bytes$' build-$board.txt)" = 2 ] ||
    say "$board: no sizes: $(cat build-$board.txt)"
  hil=$(grep -- "-bender-hil.elf\$" build-$board.txt | awk '{print $2}')
  [ -f "$hil" ] || say "$board: $hil is not there"
  # stm32f4: the .bin st-flash writes, beside each image, named and there.
  if [ $board = stm32f4 ]; then
    for bin in "$prefix-bender.bin" "$prefix-bender-hil.bin"; do
      path=$(grep -- "/$bin\$" build-$board.txt | awk '{print $1}')
      [ -n "$path" ] && [ -f "$path" ] || say "$board: $bin not reported or not there: $(cat build-$board.txt)"
    done
  fi
done
built
