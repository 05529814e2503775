#!/usr/bin/env bash
# The protocol conformance suite (nlsoft-console conformance --qemu) against a
# Cortex-M4F image in QEMU: the same checks a user runs against a board.
# BOARD (optional): mps2-an386 (default), stm32f4 or mps2-an500.
# Exit 77 (ctest: skipped) when qemu-system-arm or the image is missing.
set -u
console=$1 image=$2 platform=$3 board=${4:-mps2-an386}
command -v qemu-system-arm >/dev/null || { echo "SKIP: qemu-system-arm is not installed"; exit 77; }
[ -f "$image" ] || { echo "SKIP: $image was not built (no arm-none-eabi-g++ when configuring)"; exit 77; }
NLSOFT_M4_IMAGE=$image timeout 300 "$console" conformance --qemu "$platform" --board "$board"
