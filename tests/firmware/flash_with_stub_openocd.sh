#!/usr/bin/env bash
# `nlsoft-console flash` runs openocd as the README says: a stand-in openocd
# first on PATH records its arguments, and --no-connect stops before the
# serial port. A failing openocd is an error, not a connect.
# Exit 77 (ctest: skipped) when the image was not built.
set -u
console=$1 image=$2
[ -f "$image" ] || { echo "SKIP: $image was not built (no arm-none-eabi-g++ when configuring)"; exit 77; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat > "$dir/openocd" <<STUB
#!/bin/sh
printf '%s\n' "\$@" > "$dir/args"
exit \${STUB_STATUS:-0}
STUB
chmod +x "$dir/openocd"
PATH="$dir:$PATH" "$console" flash --board stm32f4 --rig hasel --hil --image "$image" --no-connect ||
  { echo "FAIL: flash with a working openocd failed"; exit 1; }
expected=$(printf '%s\n' -f board/st_nucleo_f4.cfg -c "program {$image} verify reset exit")
[ "$(cat "$dir/args")" = "$expected" ] || { echo "FAIL: openocd ran with:"; cat "$dir/args"; exit 1; }
out=$(STUB_STATUS=1 PATH="$dir:$PATH" "$console" flash --board stm32f4 --rig hasel --image "$image" 2>&1)
rc=$?
echo "$out"
[ "$rc" -ne 0 ] || { echo "FAIL: a failing openocd did not fail flash"; exit 1; }
grep -q "openocd failed (exit status 1)" <<<"$out" || { echo "FAIL: no word of openocd's failure"; exit 1; }
