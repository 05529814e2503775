#!/usr/bin/env bash
# Compiles the Teensy sketch (nlsoft.ino with teensy_hal.hpp and the portable
# core) for the Teensy 3.6 (Cortex-M4F, MK66FX1M0) and 4.1 (Cortex-M7,
# IMXRT1062) with Debian's arm-none-eabi-g++ and the stand-in Arduino.h of
# this folder: the port keeps up with the core's interface. Compile only:
# without Teensyduino's core nothing links, so this does not show the sketch
# runs. Exit 77 (ctest: skipped) without arm-none-eabi-g++.
#   compile_check.sh CONSOLE   (the nlsoft-console that writes the rig header, as README.md says)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../../.." && pwd)
console=${1:?give the nlsoft-console binary}
command -v arm-none-eabi-g++ >/dev/null || { echo "SKIP: arm-none-eabi-g++ is not installed"; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The sketch's nlsoft_rig.hpp, as its README has the user write it (into
# a folder of our own, so the source tree stays clean), for a shipped rig
# whose sensors and actuators the sketch drives itself (hasel's chips on SPI and
# tendon's Dynamixel servos on a USART: refused, no bus drivers without a board).
NLSOFT_RIGS="$root/rigs" "$console" firmware header --rig msd --out "$out/rig"
mapfile -t warnings < <(grep '^-' "$root/cmake/warning_flags.txt")  # the one warnings list
common=(-std=gnu++17 -fno-exceptions -fno-rtti -fno-threadsafe-statics -Os "${warnings[@]}" -Werror
  -I"$here" -I"$out/rig" -I"$root" -x c++ -c "$root/firmware/ports/teensy/nlsoft/nlsoft.ino")
arm-none-eabi-g++ -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -D__MK66FX1M0__ -DF_CPU=180000000 \
  "${common[@]}" -o "$out/teensy36.o"
echo "teensy 3.6 (cortex-m4f): compiled"
arm-none-eabi-g++ -mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard -D__IMXRT1062__ -DF_CPU=600000000 \
  "${common[@]}" -o "$out/teensy41.o"
echo "teensy 4.1 (cortex-m7): compiled"
