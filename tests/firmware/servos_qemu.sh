#!/usr/bin/env bash
# tendon as the paper built it: the stm32f4 board image of rigs/tendon.toml
# (two Dynamixel RX-64 on USART1, protocol 1.0) in QEMU's netduinoplus2,
# its USART1 on one pty with a fake chain of two RX-64 (a test program
# speaking the protocol: fake_servo_chain_main.cpp), its USART2 on another
# for the console. The servos are found (`rig check`), conformance passes,
# a closed-loop run's inputs reach the servos as the goals the rig file's
# mapping gives (512 + 195.57 u, rounded), and each way a servo fails is
# named by the console: an overload mid-run (logged, the servo held at its
# last goal), silence, an answer from another id, a corrupt checksum.
# Exit 77 (ctest: skipped) without qemu-system-arm or the image.
#   servos_qemu.sh CONSOLE IMAGE FAKE_CHAIN WORK_FOLDER
set -u
console=$1 image=$2 fake=$3 work=$4
command -v qemu-system-arm >/dev/null || { echo "SKIP: qemu-system-arm is not installed"; exit 77; }
[ -f "$image" ] || { echo "SKIP: $image was not built (no arm-none-eabi-g++ when configuring)"; exit 77; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
export XDG_CACHE_HOME=$work/cache XDG_DATA_HOME=$work/data
fail=0
say() { echo "FAIL: $*"; fail=1; }
qemu= chain=
trap '[ -n "$chain" ] && kill $chain 2>/dev/null; [ -n "$qemu" ] && kill $qemu 2>/dev/null' EXIT
# A servo answers within its return delay whatever else the host runs; the
# image waits 30 ms of emulated time (kEmulatedAnswerUs), which passes with
# the host's clock. On a loaded host the fake chain and QEMU's I/O thread
# were woken late: beside four busy loops 2 of 5 runs lost reads ("rx64-1
# stopped", a conformance check failed). So both run at nice -10 where the
# user may raise priority (root, as CI); elsewhere as they are.
urgent=()
[ "$(nice -n -10 nice 2>/dev/null)" = -10 ] && urgent=(nice -n -10)

"${urgent[@]}" qemu-system-arm -nographic -monitor none -M netduinoplus2 -serial pty -serial pty -kernel "$image" >qemu.out 2>&1 &
qemu=$!
bus= port=
for _ in $(seq 50); do
  bus=$(sed -n 's|.*redirected to \(/dev/pts/[0-9]*\) (label serial0).*|\1|p' qemu.out)
  port=$(sed -n 's|.*redirected to \(/dev/pts/[0-9]*\) (label serial1).*|\1|p' qemu.out)
  [ -n "$bus" ] && [ -n "$port" ] && break
  sleep 0.1
done
[ -n "$bus" ] && [ -n "$port" ] || { echo "FAIL: QEMU gave no ptys: $(cat qemu.out)"; exit 1; }

# chain NAME [--fault ...]: the fake chain (ids 1 and 2) on the servo bus, logging to NAME.log.
start_chain() {
  [ -n "$chain" ] && kill $chain 2>/dev/null && wait $chain 2>/dev/null
  "${urgent[@]}" "$fake" "$bus" "$1.log" --servo 1:rx-64 --servo 2:rx-64 "${@:2}" &
  chain=$!
}
# until_state DEVICE STATE: `rig check` against the board until DEVICE shows STATE (a servo
# not ok is tried again once a second), at most 20 tries a quarter second apart; its output in check.txt.
until_state() {
  for _ in $(seq 20); do
    timeout 60 "$console" rig check tendon "$port" >check.txt 2>&1
    grep -q "device $1 .*: $2\b" check.txt && return 0
    sleep 0.25
  done
  say "$1 never $2: $(cat check.txt)"
  return 1
}

start_chain healthy
until_state rx64-1 ok && until_state rx64-2 ok && cat check.txt
grep -q "device rx64-1 .*rx-64 on usart1 id 1: " check.txt || say "rx64-1 not named by bus and id: $(cat check.txt)"

timeout 300 "$console" conformance "$port" >conformance.txt 2>&1 || say "conformance: $(tail -20 conformance.txt)"
tail -3 conformance.txt

# A closed-loop run; servo 2 overloads after 150 goals away from neutral (about 1.3 s into the run).
start_chain run --fault 2:overload:150
until_state rx64-2 ok
cat >run.nls <<'NLS'
ref infinity hold=1
run 3s label=servos
expect lost == 0
expect samples >= 60
NLS
timeout 120 "$console" "$port" --rig tendon --script run.nls --db runs.db >run.txt 2>&1 || say "run: $(cat run.txt)"
cat run.txt
grep -q "firmware warn: device rx64-2 (rx-64): fault: overload; held at its last goal" run.txt ||
  say "the console did not name servo rx64-2 and its overload"
"$console" runs export 1 --csv run.csv --db runs.db >log.txt 2>&1 || say "runs export: $(cat log.txt)"
python3 - run.csv run.log run.txt <<'PY' || say "the servos' goals are not the controller's inputs"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
goals = {1: [], 2: []}
fault_at = None
for line in open(sys.argv[2]):
    w = line.split()
    if w[0] == "fault":
        fault_at = len(goals[2])
    else:
        goals[int(w[0])].append(int(w[1]))
want = lambda u: int(round(512 + 195.57 * float(u)))
# Every recorded step's u1 reaches servo 1 as a goal, in order (the run records
# a decimated subset of the steps; the chain sees every step's goal).
seq, i, matched = goals[1], 0, 0
for r in rows:
    g = want(r["u0"])
    while i < len(seq) and abs(seq[i] - g) > 1:
        i += 1
    if i < len(seq):
        matched += 1
print(f"{len(rows)} samples, {len(goals[1])} goals to servo 1 ({matched} of the samples' u found in order), "
      f"{len(goals[2])} to servo 2, its fault after {fault_at}")
ok = len(rows) >= 60 and matched == len(rows) and len(set(goals[1])) > 10
# Held: servo 2 takes no goal once the firmware read its fault: the next
# read comes within a read period (25 Hz: 5 steps) and its answer through
# the host's pty, so within 12 goals of the fault. An answer the host's
# scheduler held past the firmware's wait (seen about once in ten runs)
# makes that read fail, the servo is stopped (the console says so) and
# asked again a second later (120 goals at 120 Hz): then within 132.
said = open(sys.argv[3]).read()
stopped_at, fault_said_at = said.find("device rx64-2 (rx-64): stopped"), said.find("device rx64-2 (rx-64): fault")
stopped_first = 0 <= stopped_at < fault_said_at
slack = 132 if stopped_first else 12
print(f"servo 2 held within {slack} goals of its fault" + (" (a read lost first: stopped, asked again)" if stopped_first else ""))
ok = ok and fault_at is not None and len(goals[2]) <= fault_at + slack and len(goals[1]) > len(goals[2]) + 30
sys.exit(0 if ok else 1)
PY

# Each other way a servo fails, named by the console as the device's state:
# a silent servo is stopped at its first unanswered read, then absent once
# its retry (a PING a second later) goes unanswered too.
start_chain silent --fault 2:silent
until_state rx64-2 "\(stopped\|absent\)"
start_chain wrong --fault 2:wrong-id
until_state rx64-2 "wrong id"
start_chain corrupt --fault 2:corrupt
until_state rx64-2 stopped
start_chain again
until_state rx64-2 ok
[ $fail -eq 0 ] && echo "tendon's servos: found, driven with the controller's goals, each failure named"
exit $fail
