#!/usr/bin/env bash
# A scripted console session (nlsoft-console --qemu --script) against a HIL
# image in QEMU: connect, set a parameter, run the platform's task with the
# simulated plant, check what came back. Exit 77 (ctest: skipped) when
# qemu-system-arm or the image is missing.
set -u
console=$1 image=$2 platform=$3 board=$4 script=$5
command -v qemu-system-arm >/dev/null || { echo "SKIP: qemu-system-arm is not installed"; exit 77; }
[ -f "$image" ] || { echo "SKIP: $image was not built (no arm-none-eabi-g++ when configuring)"; exit 77; }
NLSOFT_M4_IMAGE=$image timeout 120 "$console" --qemu "$platform" --board "$board" --no-record --script "$script"
