#!/usr/bin/env bash
# A rig whose chips are on one board's buses (hasel: six LIS3MDL on
# stm32f4's SPI2) builds its HIL image for another board when asked
# (`firmware build --board mps2-an386 --hil`): the simulated plant gives
# every sensor channel, so the image reads no chip and its header says it
# is for the HIL image only; no board image is made beside it.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++.
#   hil_for_another_board.sh CONSOLE STAGE_FOLDER
set -u
console=$1 stage=$2
command -v arm-none-eabi-g++ >/dev/null || { echo "SKIP: no arm-none-eabi-g++"; exit 77; }
rm -rf "$stage" && mkdir -p "$stage" && cd "$stage" || exit 1
fail=0
"$console" firmware build --rig hasel --board mps2-an386 --hil --out fw >build.txt 2>&1 ||
  { echo "FAIL: firmware build --hil: $(cat build.txt)"; exit 1; }
cat build.txt
[ -s fw/nlsoft-m4-hasel-hil.elf ] || { echo "FAIL: no HIL image in fw: $(ls fw)"; fail=1; }
[ ! -e fw/nlsoft-m4-hasel.elf ] || { echo "FAIL: a board image of chips on another board's buses was built"; fail=1; }
grep -qF "// For the HIL image only, in which the simulated plant gives every sensor channel." \
  fw/.rig/hasel/nlsoft_rig.hpp || { echo "FAIL: the header does not say it is for the HIL image only"; fail=1; }
grep -qF "set(NLSOFT_IMAGE_BOARD 0)" fw/.rig/hasel/image.cmake || { echo "FAIL: image.cmake: $(cat fw/.rig/hasel/image.cmake)"; fail=1; }
[ $fail = 0 ] && echo "PASS"
exit $fail
