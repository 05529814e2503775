# Sourced by the tests that build a rig file's image and boot it in QEMU:
# skipped (exit 77, ctest's skip) without the ARM toolchain or QEMU; a
# scratch folder as the working directory and the console's caches; `say`
# records a failure and goes on; `json FILE EXPR` prints EXPR over the JSON
# value j.
#
# Such a test comes in two ctest parts that share a folder of the build
# tree (FIXTURES_SETUP, FIXTURES_REQUIRED), set before sourcing this:
# stage=FOLDER, part=build or qemu. The build part (training, `firmware
# build`: no QEMU) empties the folder and marks it complete when it passes;
# the qemu part (under RESOURCE_LOCK qemu) works in it, so that the lock is
# held only while an image runs, not while images compile.
command -v arm-none-eabi-g++ >/dev/null || { echo "SKIP: arm-none-eabi-g++ is not installed"; exit 77; }
command -v qemu-system-arm >/dev/null || { echo "SKIP: qemu-system-arm is not installed"; exit 77; }
[ -n "${stage:-}" ] && [ "${part:-}" = build -o "${part:-}" = qemu ] || { echo "FAIL: set stage=FOLDER part=build|qemu before sourcing $BASH_SOURCE"; exit 1; }
qemu=
work=$stage
trap '[ -n "$qemu" ] && kill "$qemu" 2>/dev/null' EXIT
if [ "$part" = build ]; then
  rm -rf "$work" && mkdir -p "$work" || exit 1
else
  [ -f "$work/.built" ] || { echo "FAIL: $work holds no complete build: its build part (ctest's fixture) did not pass"; exit 1; }
fi
cd "$work" || exit 1
export XDG_CACHE_HOME=$work/cache XDG_DATA_HOME=$work/data
unset NLSOFT_M4_IMAGE
fail=0
say() { echo "FAIL: $*"; fail=1; }
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }
# recorded LABEL MIN_SAMPLES HASH: the id of the run of that label in the
# folder's database, recorded in full with at least MIN_SAMPLES samples and
# no frame lost, whose firmware ran the model of that hash (`runs show`:
# "model <hash>"); nothing otherwise.
recorded() {
  "$console" runs list --json >runs.json 2>log.txt || { say "runs list: $(cat log.txt)"; return; }
  local id
  id=$(json runs.json "' '.join(str(r['id']) for r in j if r['label'] == '$1' and r['end_reason'] == 'completed' and r['samples'] >= $2 and r['lost_frames'] == 0)")
  [ -n "$id" ] && "$console" runs show "$id" | grep -q ", model $3, " && echo "$id"
}
# built: ends the build part, its folder marked complete when nothing failed.
built() {
  [ $fail -eq 0 ] && touch "$work/.built" && echo "built in $work"
  exit $fail
}
# boot_qemu MACHINE ELF [QEMU ARGS...]: QEMU started on the image in the
# background ($qemu), with the extra arguments (devices, a QMP socket),
# $port the pty of the UART the console talks to (USART2 on netduinoplus2,
# the second serial port); false when QEMU gave no pty in 5 s.
boot_qemu() {
  local serial=(-serial pty) label=''
  [ "$1" = netduinoplus2 ] && serial=(-serial null -serial pty) label=' (label serial1)'
  # Gone before QEMU starts: the redirection below truncates the file in the
  # background child, and a read that came first found the last boot's pty
  # there, a number another test's terminal had since been given (seen once:
  # bus_sensors' second boot "port busy", /dev/pts/0 open in a tmux pane's console).
  rm -f qemu.out
  qemu-system-arm -nographic -monitor none -M "$1" "${serial[@]}" -kernel "$2" "${@:3}" >qemu.out 2>&1 &
  qemu=$!
  port=
  for _ in $(seq 50); do
    port=$(sed -n "s|.*redirected to \(/dev/pts/[0-9]*\)$label.*|\1|p" qemu.out 2>/dev/null)
    [ -n "$port" ] && return 0
    sleep 0.1
  done
  return 1
}
