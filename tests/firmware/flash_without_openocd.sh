#!/usr/bin/env bash
# `nlsoft-console flash` on a machine without openocd: a usage error that
# names the Debian package, before any board is touched. PATH holds nothing,
# so openocd cannot be found however the host is set up.
set -u
console=$1
out=$(env PATH=/nonexistent "$console" flash --board stm32f4 --rig hasel 2>&1)
rc=$?
echo "$out"
[ "$rc" -ne 0 ] || { echo "FAIL: exit status 0 without openocd"; exit 1; }
grep -q "apt-get install openocd" <<<"$out" || { echo "FAIL: the error does not name the openocd package"; exit 1; }
