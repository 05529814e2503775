#!/usr/bin/env bash
# Sensor chips on the mps2-an386's I2C bus (the build part;
# bus_sensors_qemu.sh boots it): a rig file with an LSM303DLHC magnetometer
# at 0x1e and a DPS310 at 0x77 ([[device]]) whose five channels are its
# sensors builds the plain mps2-an386 image (`firmware build --board
# mps2-an386`), its generated header listing both chips.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   bus_sensors_build.sh CONSOLE STAGE_FOLDER
set -u
console=$1
stage=$2 part=build
. "$(dirname "$0")/rig_image_test_prelude.sh"

cat >chips.toml <<'EOF2'
name = "chips"
rate_hz = 50.0
nd = 1
dd = 1
board = "mps2-an386"

[[input]]
name = "u"
min = 0.0
max = 1.0
neutral = 0.5

[[output]]
name = "y"
min = -1.0
max = 1.0

[[device]]
name = "mag"
chip = "lsm303dlhc_mag"
bus = "i2c-shield1"   # where QEMU puts a -device without bus=
address = 0x1e
range = 1.3
rate_hz = 75

[[device]]
name = "air"
chip = "dps310"
bus = "i2c-shield1"
rate_hz = 8

[[sensor]]
name = "mx"
unit = "uT"
source = "device"
device = "mag"
channel = "x"

[[sensor]]
name = "my"
unit = "uT"
source = "device"
device = "mag"
channel = "y"

[[sensor]]
name = "mz"
unit = "uT"
source = "device"
device = "mag"
channel = "z"

[[sensor]]
name = "p"
unit = "kPa"
source = "device"
device = "air"
channel = "pressure"
gain = 0.001

[[sensor]]
name = "t"
unit = "degC"
source = "device"
device = "air"
channel = "temperature"

[controller]
Q = [1.0]
Lambda = [1.0]
s = 1e-20
b = 0.0
r = 2.0
N = 3
Nc = 1
eps = 1e-3

[model]
[[model.layer]]
kind = "dense"
units = 1
EOF2

"$console" rig check chips.toml >check.txt 2>&1 || { cat check.txt; echo "FAIL: rig check"; exit 1; }
"$console" firmware build --rig chips.toml --board mps2-an386 >build.txt 2>&1 || { cat build.txt; echo "FAIL: firmware build"; exit 1; }
cat build.txt
elf=$(grep -- "/nlsoft-m4-chips.elf\$" build.txt | awk '{print $2}')
[ -f "$elf" ] || { echo "FAIL: no board image reported: $(cat build.txt)"; exit 1; }
grep -q "kRigDeviceCount = 2;" "$(dirname "$elf")/.rig/chips/nlsoft_rig.hpp" ||
  say "the generated header lists no chips: $(cat "$(dirname "$elf")/.rig/chips/nlsoft_rig.hpp")"
built
