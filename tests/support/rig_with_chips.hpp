#pragma once
// A rig file with sensor chips on all three of the stm32f4 board's buses:
// an LSM303DLHC magnetometer and a DPS310 on i2c1, a LIS3MDL on spi1 (chip
// select PA8), each read by a sensor. The loader's tests edit it; the
// console's tests take it as a firmware's rig.
namespace nlsoft::test {

inline const char* const kRigWithChips = R"(name = "mags"
rate_hz = 100.0
nd = 1
dd = 1

[[input]]
name = "u1"
min = 0.0
max = 1.0
neutral = 0.5
pwm = "PC6"

[[output]]
name = "x"
min = -10.0
max = 10.0

[[device]]
name = "tip"
chip = "lsm303dlhc_mag"
bus = "i2c1"
address = 0x1e
range = 1.3
rate_hz = 75

[[device]]
name = "air"
chip = "dps310"
bus = "i2c1"
rate_hz = 16

[[device]]
name = "ring1"
chip = "lis3mdl"
bus = "spi1"
cs = "PA8"
clock_hz = 1000000
range = 16
rate_hz = 1000

[[sensor]]
name = "tip_x"
unit = "uT"
source = "device"
device = "tip"
channel = "x"

[[sensor]]
name = "p"
unit = "kPa"
source = "device"
device = "air"
channel = "pressure"
gain = 0.001

[[sensor]]
name = "ring1_z"
source = "device"
device = "ring1"
channel = "z"
offset = -3.0

[controller]
Q = [1.0]
Lambda = [1.0]
s = 1e-20
b = 1e-5
r = 400.0
N = 3
Nc = 1
eps = 0.01
)";

}  // namespace nlsoft::test
