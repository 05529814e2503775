#!/usr/bin/env bash
# `model upload` of the authors' Dense 36->10->5->3 to the hasel Cortex-M4F
# image in QEMU, whose kernel runs 36->5->5->3 only: the console refuses it
# from RIG_INFO before sending a byte, in one sentence, and the script exits 2.
# Exit 77 (ctest: skipped) when qemu-system-arm or the image is missing.
set -u
console=$1 image=$2
command -v qemu-system-arm >/dev/null || { echo "SKIP: qemu-system-arm is not installed"; exit 77; }
[ -f "$image" ] || { echo "SKIP: $image was not built (no arm-none-eabi-g++ when configuring)"; exit 77; }
dir=$(mktemp -d) && trap 'rm -rf "$dir"' EXIT
# The model file (shared/model_file.hpp's layout), zero weights.
python3 - "$dir/model.nlsm" <<'PY'
import struct, sys, zlib
m, n, w, nd, units = 6, 3, 18, 2, [10, 5, 3]
p = nd * (m + n) + w
params, i = 2 * p + 2 * n, p
for u in units:
    params, i = params + i * u + u, u
f = bytearray(b"NLSM") + bytes([1, 0, m, n, w, nd, nd, len(units)]) + struct.pack("<I", params) + bytes([1]) + bytes(7)
i = p
for l, u in enumerate(units):
    f += bytes([1, 2 if l < 2 else 0, 3, 1]) + struct.pack("<HH", i, u)
    i = u
f += bytes(4 * params)
f += struct.pack("<I", zlib.crc32(bytes(f)))
open(sys.argv[1], "wb").write(f)
PY
echo "model upload model.nlsm" > "$dir/up.nls"
cd "$dir" || exit 1
out=$(NLSOFT_M4_IMAGE=$image timeout 120 "$console" --qemu hasel --no-record --script up.nls 2>&1)
rc=$?
echo "$out"
[ $rc -eq 2 ] || { echo "FAIL: exit $rc, expected 2"; exit 1; }
want="model.nlsm is Dense 36->10->5->3; this firmware (rig hasel) accepts Dense 36->5->5->3 only"
grep -qF "$want" <<<"$out" || { echo "FAIL: no line '$want'"; exit 1; }
grep -q "rig hasel" <<<"$out" || { echo "FAIL: the connected line does not name the rig"; exit 1; }
echo "PASS"
