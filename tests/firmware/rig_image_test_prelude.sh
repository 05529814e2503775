# Sourced by the tests that build a rig file's image and boot it in QEMU:
# skipped (exit 77, ctest's skip) without the ARM toolchain or QEMU; a
# scratch folder as the working directory and the console's caches, removed
# at exit with a QEMU the test started ($qemu, when set); `say` records a
# failure and goes on; `json FILE EXPR` prints EXPR over the JSON value j.
command -v arm-none-eabi-g++ >/dev/null || { echo "SKIP: arm-none-eabi-g++ is not installed"; exit 77; }
command -v qemu-system-arm >/dev/null || { echo "SKIP: qemu-system-arm is not installed"; exit 77; }
work=$(mktemp -d)
qemu=
trap '[ -n "$qemu" ] && kill "$qemu" 2>/dev/null; rm -rf "$work"' EXIT
cd "$work" || exit 1
export XDG_CACHE_HOME=$work/cache XDG_DATA_HOME=$work/data
unset NLSOFT_M4_IMAGE
fail=0
say() { echo "FAIL: $*"; fail=1; }
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }
# boot_qemu MACHINE ELF: QEMU started on the image in the background ($qemu),
# $port the pty of the UART the console talks to (USART2 on netduinoplus2,
# the second serial port); false when QEMU gave no pty in 5 s.
boot_qemu() {
  local serial=(-serial pty) label=''
  [ "$1" = netduinoplus2 ] && serial=(-serial null -serial pty) label=' (label serial1)'
  qemu-system-arm -nographic -monitor none -M "$1" "${serial[@]}" -kernel "$2" >qemu.out 2>&1 &
  qemu=$!
  port=
  for _ in $(seq 50); do
    port=$(sed -n "s|.*redirected to \(/dev/pts/[0-9]*\)$label.*|\1|p" qemu.out)
    [ -n "$port" ] && return 0
    sleep 0.1
  done
  return 1
}
