#!/usr/bin/env bash
# Ctrl-C during `firmware build`, as a terminal sends it (SIGINT to the
# console's process group) once the linker has begun writing an image: the
# console stops the build tools, says that the folder holds the images it
# held before, exits 130; the images and maps there are the earlier ones,
# byte for byte, with no part of a new one beside them; and so is the
# folder's record of what they were built from (model.nlsm, .rig/): it
# named the new model beside the old images.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++.
#   firmware_build_interrupt.sh CONSOLE SOURCE_DIR WORK_FOLDER
set -u
console=$1 src=$2 work=$3
command -v arm-none-eabi-g++ >/dev/null || { echo "SKIP: arm-none-eabi-g++ is not installed"; exit 77; }
rm -rf "$work" && mkdir -p "$work/out" "$work/home" || exit 1
cd "$work" || exit 1
export HOME=$work/home XDG_CACHE_HOME=$work/cache
fail=0
say() { echo "FAIL: $*"; fail=1; }

# The images an earlier build left.
printf 'the earlier image\n' >out/nlsoft-m4-msd-hil.elf
printf 'the earlier map\n' >out/nlsoft-m4-msd-hil.map
printf 'the earlier model\n' >out/model.nlsm
mkdir -p out/.rig/msd && printf 'the earlier record\n' >out/.rig/msd/image.cmake
touch stamp
setsid "$console" firmware build --rig "$src/rigs/msd.toml" --board mps2-an386 --hil --out out >log.txt 2>&1 &
console_pid=$!
# Until the linker opens its map (it writes the image after), or the console ends.
linking=
while kill -0 $console_pid 2>/dev/null; do
  linking=$(find out -newer stamp \( -name '*.map' -o -name '*.elf' \) -print -quit)
  [ -n "$linking" ] && break
  sleep 0.05
done
[ -n "$linking" ] || say "the build ended before it linked: $(cat log.txt)"
echo "interrupting as $linking appeared"
kill -INT -- -$console_pid
wait $console_pid
rc=$?
cat log.txt
[ $rc -eq 130 ] || say "exit $rc after Ctrl-C, not 130"
grep -qF "firmware build: interrupted: the images in $work/out are the ones it held before" log.txt ||
  say "the console did not say what it left"
[ "$(cat out/nlsoft-m4-msd-hil.elf)" = "the earlier image" ] || say "the earlier image was replaced"
[ "$(cat out/nlsoft-m4-msd-hil.map)" = "the earlier map" ] || say "the earlier map was replaced"
[ "$(cat out/model.nlsm)" = "the earlier model" ] || say "model.nlsm names the interrupted build's model"
[ "$(cat out/.rig/msd/image.cmake)" = "the earlier record" ] || say ".rig/msd/image.cmake is the interrupted build's"
# Beside them only the build's log and the model it embeds; the rest is in the hidden build folders.
left=$(cd out && ls | sort | tr '\n' ' ')
[ "$left" = "build.log model.nlsm nlsoft-m4-msd-hil.elf nlsoft-m4-msd-hil.map " ] || say "the folder holds: $left"
# No build tool left running (given 10 s to finish dying).
for _ in $(seq 100); do pgrep -f "$work/out/.build" >/dev/null || break; sleep 0.1; done
pgrep -f "$work/out/.build" >/dev/null && say "build tools still run: $(pgrep -af "$work/out/.build")"
exit $fail
