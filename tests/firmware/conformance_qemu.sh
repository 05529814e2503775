#!/usr/bin/env bash
# The protocol conformance suite (nlsoft-console conformance) against the
# Cortex-M4F image in QEMU: the same checks a user runs against a board.
# Exit 77 (ctest: skipped) when qemu-system-arm or the image is missing.
set -u
console=$1 image=$2
command -v qemu-system-arm >/dev/null || { echo "SKIP: qemu-system-arm is not installed"; exit 77; }
[ -f "$image" ] || { echo "SKIP: $image was not built (no arm-none-eabi-g++ when configuring)"; exit 77; }
log=$(mktemp)
qemu-system-arm -M mps2-an386 -nographic -monitor none -serial pty -icount shift=0 -kernel "$image" >"$log" 2>&1 &
qemu=$!
trap 'kill $qemu 2>/dev/null; wait $qemu 2>/dev/null; rm -f "$log"' EXIT
pty=""
for _ in $(seq 50); do
  pty=$(grep -o '/dev/pts/[0-9]*' "$log" | head -n 1)
  [ -n "$pty" ] && break
  sleep 0.1
done
[ -n "$pty" ] || { echo "QEMU reported no pty:"; cat "$log"; exit 1; }
timeout 120 "$console" conformance "$pty"
