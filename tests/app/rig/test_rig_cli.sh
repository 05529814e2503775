#!/usr/bin/env bash
# Rig files as a user meets them, through the real console: `rig check` and
# `rig list`, a bad file's one line with file:line and key, `--rig`/`--sim`
# taking a name or a path, and a rig the firmware or the simulator does not
# carry refused with what is missing.
#   test_rig_cli.sh CONSOLE SOURCE_DIR FIRMWARE_SIM
set -u
console=$1 src=$2 firmware_sim=$3
fail=0
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1

expect_error() {  # expect_error "pattern" args...: exit 2 and the pattern in the output
  local pattern=$1
  shift
  out=$("$console" "$@" 2>&1)
  rc=$?
  if [ $rc -ne 2 ] || ! grep -qF -- "$pattern" <<<"$out"; then
    echo "FAIL: '$*' gave rc=$rc: $out"
    fail=1
  fi
}
field() {  # field FILE KEY: a top-level value of a JSON object
  python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"
}

# The shipped rigs, by name.
[ "$("$console" rig list | cut -d' ' -f1 | tr '\n' ' ')" = "hasel msd tendon " ] ||
  { echo "FAIL: rig list: $("$console" rig list)"; fail=1; }
"$console" rig check hasel >out.txt || { echo "FAIL: rig check hasel"; fail=1; }
grep -qF "w = 18 sensors: 0 on ADC1, 18 from chips" out.txt ||
  { echo "FAIL: hasel summary: $(cat out.txt)"; fail=1; }
grep -qE "^    device mag6 +lis3mdl on spi2 chip select PB5, 16 gauss, 155 Hz$" out.txt ||
  { echo "FAIL: hasel's sixth magnetometer: $(cat out.txt)"; fail=1; }
"$console" rig check --json "$src/rigs/tendon.toml" >tendon.json || { echo "FAIL: rig check --json"; fail=1; }
[ "$(field tendon.json m) $(field tendon.json n) $(field tendon.json w)" = "2 3 11" ] ||
  { echo "FAIL: tendon dims: $(cat tendon.json)"; fail=1; }

# A bad file: one line, file:line and key, exit 2.
sed 's/^max = 1.0$/max = 0.0/' "$src/rigs/hasel.toml" >bad.toml
line=$(grep -n '^max = 0.0$' bad.toml | head -1 | cut -d: -f1)
expect_error "bad.toml:$line: [[input]] #1 max: must be > min (0 at line $((line - 1)))" rig check bad.toml
expect_error "unknown rig 'nope'; rigs in" rig check nope
expect_error "rig file './none.toml' does not exist" rig check ./none.toml
# What is there but is no rig file is said as what it is.
ln -s /dev/zero zero.toml && mkfifo fifo.toml && mkdir dir.toml || { echo "FAIL: cannot make the odd files"; fail=1; }
expect_error "cannot read zero.toml: it is a character device, not a rig file" rig check zero.toml
expect_error "cannot read fifo.toml: it is a FIFO, not a rig file" rig check fifo.toml
expect_error "cannot read dir.toml: it is a directory, not a rig file" rig check dir.toml
expect_error "cannot read fifo.toml: it is a FIFO, not a rig file" simulate --rig fifo.toml

# Text that would leave its place: a name holding a line of C++, a model
# file out of the models folder (simulate would open /etc/passwd).
python3 - "$src/rigs/msd.toml" <<'EOF2'
import sys
t = open(sys.argv[1]).read()
open("inject.toml", "w").write(t.replace('name = "u"', 'name = "a\\n#include \\"/etc/hostname\\""', 1))
open("trav.toml", "w").write(t.replace('file = "msd.nlsm"', 'file = "../../../../../../etc/passwd"', 1))
EOF2
line=$(grep -n '^name = "a' inject.toml | cut -d: -f1)
expect_error "inject.toml:$line: [[input]] #1 name: 'a\n#include \"/etc/hostname\"' is not a name" rig check inject.toml
line=$(grep -n '^file = ' trav.toml | cut -d: -f1)
expect_error "trav.toml:$line: [model] file: '../../../../../../etc/passwd' is not a file name among the models" \
  rig check trav.toml
expect_error "trav.toml:$line: [model] file:" simulate --rig trav.toml

# A rig with no [plant]: checked, but neither simulated nor booted in QEMU
# (its image has no plant in the loop).
sed -e 's/^name = "hasel"/name = "arm"/' -e '/^\[plant\]/,/^kind/d' "$src/rigs/hasel.toml" >arm.toml
"$console" rig check arm.toml >/dev/null || { echo "FAIL: arm.toml does not load"; fail=1; }
expect_error "simulate: rig 'arm' (arm.toml) has no [plant]: nothing simulates it" simulate --rig arm.toml
expect_error "--sim: rig 'arm' (arm.toml) has no [plant]: nothing simulates it" --sim arm.toml
expect_error "rig 'arm' has no [plant]: nothing simulates it, so there is no data to record" \
  dataset --rig arm.toml --out arm.csv --steps 500
[ ! -e arm.csv ] || { echo "FAIL: dataset of a rig without [plant] wrote arm.csv"; fail=1; }
expect_error "--qemu: rig 'arm' (arm.toml) has no [plant]: QEMU runs an image with the simulated plant" \
  conformance --qemu arm.toml

# A copy of hasel with another tuning: the firmware simulator serves the
# file's own defaults (an image is built from it: tests/firmware/firmware_build_qemu.sh).
sed 's/^Q = \[1e6, 2e6, 1e6\]/Q = [1e6, 2e6, 1e3]/' "$src/rigs/hasel.toml" >soft.toml
printf 'get Q\n' >getq.nls
"$console" --sim soft.toml --no-record --script getq.nls >soft.txt 2>&1 || { echo "FAIL: --sim soft.toml: $(cat soft.txt)"; fail=1; }
grep -qE "^Q = 1e\+06 2e\+06 1000( |$)" soft.txt || { echo "FAIL: --sim soft.toml does not serve its Q: $(cat soft.txt)"; fail=1; }

# `firmware build` on a machine without the Cortex-M toolchain (a PATH with
# cmake alone) says what to install, before building anything.
mkdir nobin && ln -s "$(command -v cmake)" nobin/cmake
out=$(PATH="$work/nobin" "$console" firmware build --rig hasel --board stm32f4 --out fw 2>&1)
rc=$?
if [ $rc -ne 2 ] || ! grep -qF "not found: arm-none-eabi-g++, arm-none-eabi-size. Install it: apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi cmake" <<<"$out" || [ -e fw ]; then
  echo "FAIL: firmware build without a toolchain gave rc=$rc: $out"
  fail=1
fi

# hasel's chips are on stm32f4's SPI2: its board image for mps2-an386 is
# refused at the first [[device]], before anything is built.
line=$(grep -n '^\[\[device\]\]' "$src/rigs/hasel.toml" | head -1 | cut -d: -f1)
out=$("$console" firmware build --rig hasel --board mps2-an386 --out fw-an386 2>&1)
rc=$?
if [ $rc -ne 2 ] || ! grep -qF "hasel.toml:$line: [[device]] #1: device 'mag1' is on bus spi2 of board stm32f4: build the image for stm32f4, not mps2-an386 (a HIL image, which reads no chip, builds for any board)" <<<"$out" || [ -e fw-an386 ]; then
  echo "FAIL: firmware build of hasel's board image for mps2-an386 gave rc=$rc: $out"
  fail=1
fi

# A --board that is no board's, or a board that cannot do what the command
# does, is refused with the boards (from the board table) and their cores,
# before anything is built or booted.
boards="mps2-an386 (Cortex-M4F, QEMU's MPS2 AN386), stm32f4 (Cortex-M4F, a Nucleo-64; in QEMU, the STM32F405 of netduinoplus2), mps2-an500 (Cortex-M7, QEMU's MPS2 AN500), mps2-an385 (Cortex-M3, QEMU's MPS2 AN385, in a small part's 64 kB of flash and 20 kB of RAM)"
expect_error "--board: nucleo: no such board; the boards: $boards" firmware build --rig hasel --board nucleo --out fw-nucleo
[ -e fw-nucleo ] && { echo "FAIL: firmware build --board nucleo made fw-nucleo"; fail=1; }
expect_error "--board: nucleo: no such board; the boards: $boards" --qemu hasel --board nucleo
expect_error "--board: nucleo: no such board; the boards: $boards" conformance --qemu hasel --board nucleo
expect_error "--board: mps2-an500: board mps2-an500 cannot be flashed (no openocd configuration: QEMU runs its images); the boards that can: stm32f4 (Cortex-M4F," \
  flash --rig hasel --board mps2-an500

# `--rig FILE` is `--platform NAME` when the file is the shipped one, and a
# changed file changes the run.
"$console" simulate --platform hasel --steps 400 --json >by_name.json || { echo "FAIL: simulate hasel"; fail=1; }
"$console" simulate --rig "$src/rigs/hasel.toml" --steps 400 --json >by_path.json || { echo "FAIL: --rig path"; fail=1; }
"$console" simulate --rig soft.toml --steps 400 --json >soft.json || { echo "FAIL: --rig soft.toml"; fail=1; }
[ "$(field by_name.json rmse)" = "$(field by_path.json rmse)" ] ||
  { echo "FAIL: by name $(field by_name.json rmse), by path $(field by_path.json rmse)"; fail=1; }
[ "$(field by_name.json rmse)" != "$(field soft.json rmse)" ] || { echo "FAIL: soft.toml's Q changed nothing"; fail=1; }

# dataset and train: --platform NAME is the shipped file, and --rig takes it by path.
"$console" dataset --platform msd --out by_name.csv --steps 600 >/dev/null || { echo "FAIL: dataset --platform"; fail=1; }
"$console" dataset --rig "$src/rigs/msd.toml" --out by_path.csv --steps 600 >/dev/null || { echo "FAIL: dataset --rig"; fail=1; }
cmp -s by_name.csv by_path.csv || { echo "FAIL: dataset by name and by path differ"; fail=1; }
"$console" train --platform msd --data by_name.csv --out by_name.nlsm >/dev/null || { echo "FAIL: train --platform"; fail=1; }
"$console" train --rig "$src/rigs/msd.toml" --data by_path.csv --out by_path.nlsm >/dev/null || { echo "FAIL: train --rig"; fail=1; }
cmp -s by_name.nlsm by_path.nlsm || { echo "FAIL: train by name and by path differ"; fail=1; }
expect_error "by_name.csv has m=1 n=1 w=0 but rig 'hasel' has m=6" train --rig hasel --data by_name.csv --out x.nlsm

# A generic rig of four outputs: the paths drive the first three, the fourth
# holds the middle of its range (2.5 of [0, 5]), in the trace simulate writes.
{
  printf 'name = "four"\nrate_hz = 50.0\nnd = 2\ndd = 2\n\n'
  printf '[[input]]\nname = "u%s"\nmin = -1.0\nmax = 1.0\nneutral = 0.0\n\n' 1 2
  printf '[[output]]\nname = "y%s"\nmin = -4.0\nmax = 4.0\n\n' 1 2 3
  printf '[[output]]\nname = "y4"\nmin = 0.0\nmax = 5.0\n\n'
  printf '[controller]\nQ = [1.0, 1.0, 1.0, 1.0]\nLambda = [1.0, 1.0]\ns = 1e-20\nb = 0.0\nr = 4.0\nN = 3\nNc = 1\neps = 1e-3\n\n'
  printf '[plant]\nkind = "generic"\ncoupling = [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [0.5, -0.5]]\n'
  printf '[[plant.actuator]]\ntau = 0.05\n[[plant.actuator]]\nshape = "tanh"\nknee = 0.5\n'
} >four.toml
"$console" dataset --rig four.toml --out four.csv --steps 500 >/dev/null || { echo "FAIL: dataset four.toml"; fail=1; }
"$console" train --rig four.toml --data four.csv --out four.nlsm --epochs 2 >/dev/null 2>&1 || { echo "FAIL: train four.toml"; fail=1; }
"$console" simulate --rig four.toml --model four.nlsm --steps 30 --csv four_trace.csv >/dev/null ||
  { echo "FAIL: simulate four.toml"; fail=1; }
held=$(python3 -c 'import csv,sys; print(sorted({r["y_ref3"] for r in csv.DictReader(open(sys.argv[1]))}))' four_trace.csv)
[ "$held" = "['2.5']" ] || { echo "FAIL: y_ref3 is $held, want the middle of [0, 5] throughout"; fail=1; }
moving=$(python3 -c 'import csv,sys; print(len({r["y_ref1"] for r in csv.DictReader(open(sys.argv[1]))}))' four_trace.csv)
[ "$moving" -gt 20 ] || { echo "FAIL: y_ref1 takes $moving values: the Infinity does not drive it"; fail=1; }

# --sim takes a path to a shipped rig as it takes the name.
printf 'run 200ms label=by-path\n' >run.nls
"$console" --sim "$src/rigs/msd.toml" --sim-fast --no-record --script run.nls >sim.txt 2>&1 ||
  { echo "FAIL: --sim path: $(tail -5 sim.txt)"; fail=1; }

# Sensor chips: the summary lists them; `rig check RIG PORT` asks the
# firmware how each answers. The simulator simulates its sensors and has no
# chips: a file that names one finds it missing there (exit 1).
python3 - "$src/rigs/msd.toml" <<'EOF2'
import sys
t = open(sys.argv[1]).read()
chip = ('[[device]]\nname = "tip"\nchip = "lsm303dlhc_mag"\nbus = "i2c1"\nrange = 1.3\nrate_hz = 75\n\n'
        '[[sensor]]\nname = "tip_x"\nunit = "uT"\nsource = "device"\ndevice = "tip"\nchannel = "x"\n\n[controller]')
open("chips.toml", "w").write(t.replace("[controller]", chip, 1).replace('[plant]\nkind = "msd"', ""))
EOF2
"$console" rig check chips.toml >chips.txt 2>&1 || { echo "FAIL: rig check chips.toml: $(cat chips.txt)"; fail=1; }
grep -qF "w = 1 sensors: 0 on ADC1, 1 from chips" chips.txt && grep -qF "device tip        lsm303dlhc_mag on i2c1 at 0x1e, 1.3 gauss, 75 Hz" chips.txt ||
  { echo "FAIL: chips summary: $(cat chips.txt)"; fail=1; }
"$firmware_sim" --rig "$src/rigs/msd.toml" >sim_port.txt 2>sim_err.txt &
sim_pid=$!
for _ in $(seq 50); do [ -s sim_port.txt ] && break; sleep 0.1; done
port=$(head -1 sim_port.txt)
"$console" rig check msd "$port" >live.txt 2>&1 || { echo "FAIL: rig check msd PORT: $(cat live.txt)"; fail=1; }
grep -qF "rig 'msd' (0x" live.txt && grep -qF "no sensor chips, in the file or the firmware" live.txt ||
  { echo "FAIL: live msd: $(cat live.txt)"; fail=1; }
"$console" rig check chips.toml "$port" >live_chips.txt 2>&1
rc=$?
[ $rc -eq 1 ] && grep -qF "built from another file than this one" live_chips.txt &&
  grep -qF "device tip        lsm303dlhc_mag: not in the firmware" live_chips.txt ||
  { echo "FAIL: live chips.toml gave rc=$rc: $(cat live_chips.txt)"; fail=1; }
kill $sim_pid 2>/dev/null
wait $sim_pid 2>/dev/null

[ $fail -eq 0 ] && echo "rig CLI: all checks passed"
exit $fail
