#!/usr/bin/env bash
# Sensor chips on the mps2-an386's I2C bus (the qemu part;
# bus_sensors_build.sh built the image of chips.toml), against chip models
# nobody here wrote: QEMU 7.2's lsm303dlhc_mag at 0x1e and dps310 at 0x77.
# `rig check chips.toml PORT` finds both ok; an identification run's
# sensor channels are the field QMP's qom-set gives the magnetometer
# (mag-x/y/z, 1 = 0.001 uT), read at the datasheet's gain (1100 LSB/gauss
# for x and y, 980 for z at 1.3 gauss), and follow it when it changes. The
# DPS310 cannot be read through the AN386's bit-banged SBCON in QEMU 7.2: its
# bitbang_i2c model ends the transfer at the repeated START of a register
# read, and the dps310 model then answers 0xff (the bus masters' own probe
# test shows the same byte): the image reports it as a wrong identity and
# its channels invalid, never as readings. The same image with the DPS310
# left out says it is absent (exit 1), its channels recorded invalid.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   bus_sensors_qemu.sh CONSOLE STAGE_FOLDER
set -u
console=$1
stage=$2 part=qemu
. "$(dirname "$0")/rig_image_test_prelude.sh"

elf=$(grep -- "/nlsoft-m4-chips.elf\$" build.txt | awk '{print $2}')
[ -f "$elf" ] || { echo "FAIL: no board image in build.txt: $(cat build.txt)"; exit 1; }

# qom MAG_X MAG_Y MAG_Z: the magnetometer's field, 0.001 uT units, through QMP.
qom() {
  python3 - "$work/qmp.sock" "$@" <<'EOF2'
import json, socket, sys
s = socket.socket(socket.AF_UNIX)
s.connect(sys.argv[1])
f = s.makefile("rw")
def call(cmd, **args):
    f.write(json.dumps({"execute": cmd, "arguments": args} if args else {"execute": cmd}) + "\n")
    f.flush()
    while True:
        r = json.loads(f.readline())
        if "return" in r or "error" in r:
            if "error" in r: sys.exit(f"QMP {cmd}: {r['error']}")
            return r["return"]
json.loads(f.readline())  # greeting
call("qmp_capabilities")
for axis, v in zip("xyz", sys.argv[2:5]):
    call("qom-set", path="/machine/peripheral/mag", property="mag-" + axis, value=int(v))
EOF2
}
# run LABEL: a 2 s identification run recorded as LABEL; its samples in LABEL.csv.
run() {
  timeout 120 "$console" ident "$port" --rig chips.toml --signal prbs --duration 2s --label "$1" --db runs.db \
    >"$1.txt" 2>&1 || say "ident $1: $(cat "$1.txt")"
  local id
  id=$("$console" runs list --json --db runs.db | python3 -c "import json,sys; print([r['id'] for r in json.load(sys.stdin) if r['label'] == '$1'][0])")
  "$console" runs export "$id" --csv "$1.csv" --db runs.db >log.txt 2>&1 || say "runs export $1: $(cat log.txt)"
  echo "$id"
}
# near CSV COLUMN VALUE: every sample's COLUMN within 1e-3 (relative above 1)
# of VALUE, at least 40 samples.
near() {
  python3 - "$@" <<'EOF2'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
col, want = sys.argv[2], float(sys.argv[3])
bad = [r[col] for r in rows if r[col] == "" or abs(float(r[col]) - want) > 1e-3 * max(1.0, abs(want))]
print(f"{sys.argv[1]} {col}: {len(rows)} samples, first {rows[0][col] if rows else None}, want {want}")
sys.exit(1 if bad or len(rows) < 40 else 0)
EOF2
}

boot_qemu mps2-an386 "$elf" -qmp "unix:$work/qmp.sock,server=on,wait=off" \
  -device lsm303dlhc_mag,address=0x1e,id=mag -device dps310,address=0x77 ||
  { echo "FAIL: QEMU gave no pty: $(cat qemu.out)"; exit 1; }
qom 50000 25000 10000 || say "qom-set"
"$console" rig check chips.toml "$port" >live.txt 2>&1
rc=$?
cat live.txt
[ $rc -eq 1 ] || say "rig check with a chip QEMU garbles gave rc=$rc"
grep -q "device mag .* lsm303dlhc_mag on i2c-shield1 at 0x1e: ok" live.txt || say "mag not ok: $(cat live.txt)"
grep -q "device air .* dps310 on i2c-shield1 at 0x77: wrong id, no sample yet" live.txt ||
  say "air not a wrong id: $(cat live.txt)"

# 0.5 gauss is 550 LSB on x, 0.25 gauss 275 on y, 0.1 gauss 98 on z: 50, 25, 10 uT.
run field1 >/dev/null
near field1.csv l0 50 && near field1.csv l1 25 && near field1.csv l2 10 || say "the channels are not the field set"
qom 100000 180000 33000 || say "qom-set"
run field2 >/dev/null
# 1 gauss: 1100 LSB; 1.8 gauss: 1980; 0.33 gauss: 323.4, stored as 323 LSB (the model keeps whole LSB): 32.959 uT.
near field2.csv l0 100 && near field2.csv l1 180 && near field2.csv l2 32.959184 || say "the channels did not follow the field"
# health STEM: the run's SENSOR_HEALTH rows, every step with only the DPS310's channels (3, 4) invalid.
health() {
  python3 - runs.db "$1" <<'EOF2'
import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
run = db.execute("SELECT id FROM runs WHERE label=?", (sys.argv[2],)).fetchone()[0]
rows = db.execute("SELECT invalid FROM sensor_health WHERE run_id=?", (run,)).fetchall()
print(len(rows), "steps of sensor health; invalid masks:", sorted({r[0] for r in rows}))
sys.exit(0 if len(rows) >= 40 and {r[0] for r in rows} == {0b11000} else 1)
EOF2
}
health field1 || say "the DPS310's channels are not recorded invalid"
kill "$qemu" 2>/dev/null
wait "$qemu" 2>/dev/null
qemu=

# The DPS310 left out: said absent (exit 1), its channels recorded invalid.
boot_qemu mps2-an386 "$elf" -device lsm303dlhc_mag,address=0x1e,id=mag ||
  { echo "FAIL: QEMU gave no pty: $(cat qemu.out)"; exit 1; }
"$console" rig check chips.toml "$port" >absent.txt 2>&1
rc=$?
cat absent.txt
[ $rc -eq 1 ] && grep -q "device air .* dps310 on i2c-shield1 at 0x77: absent, no sample yet" absent.txt ||
  say "rig check without the DPS310 gave rc=$rc: $(cat absent.txt)"
run absent >/dev/null
health absent || say "the absent DPS310's channels are not recorded invalid"

[ $fail -eq 0 ] && echo "sensor chips on I2C: found, read at the datasheet's scale, followed; a garbled and a missing one reported"
exit $fail
