#!/usr/bin/env bash
# An image with only what its rig uses (the build part; minimal_image_qemu.sh
# boots it): msd's and hasel's shipped rig files with `[firmware] features
# = []` build images without identification runs, transfers or saved
# settings, whose code is not linked at all (none of those services'
# symbols in the ELF; the build's no-heap check passes on them) and which
# are smaller than the images of the same rig with every service (hasel's
# board image within issue #57's bound, without libm's fmodf, drivers its
# rig and services do not use, or activations its model lacks); with
# `optimize = "size"` as well, smaller again (the generic kernel, the
# controller at -Os).
# A file that asks a board for a service it cannot carry is refused at the
# list's line.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   minimal_image_build.sh CONSOLE ROOT STAGE_FOLDER
set -u
console=$1 root=$2
stage=$3 part=build
. "$(dirname "$0")/rig_image_test_prelude.sh"

minimal() {  # minimal RIG: RIG-min.toml, the shipped file renamed with no service beyond the minimum
  sed "s/^name = \"$1\"/name = \"$1-min\"/" "$root/rigs/$1.toml" >"$1-min.toml"
  printf '\n[firmware]\nfeatures = []\n' >>"$1-min.toml"
}
minimal msd
minimal hasel
sed 's/^name = "hasel"/name = "hasel-full"/' "$root/rigs/hasel.toml" >hasel-full.toml
sed 's/^name = "hasel-min"/name = "hasel-small"/' hasel-min.toml >hasel-small.toml
printf 'optimize = "size"\n' >>hasel-small.toml
flash_of() { sed -n 's/.*flash \([0-9]*\) bytes.*/\1/p' "$1" | head -1; }

for board in mps2-an386 stm32f4; do
  "$console" firmware build --rig msd-min.toml --board $board >build-msd-$board.txt 2>&1 ||
    say "firmware build --rig msd-min.toml --board $board: $(tail -5 build-msd-$board.txt)"
done
"$console" firmware build --rig hasel-min.toml --board stm32f4 >build-hasel.txt 2>&1 ||
  say "firmware build --rig hasel-min.toml --board stm32f4: $(tail -5 build-hasel.txt)"
cat build-hasel.txt
"$console" firmware build --rig hasel-full.toml --board stm32f4 >build-full.txt 2>&1 ||
  say "firmware build --rig hasel-full.toml --board stm32f4: $(tail -5 build-full.txt)"
"$console" firmware build --rig hasel-small.toml --board stm32f4 >build-small.txt 2>&1 ||
  say "firmware build --rig hasel-small.toml --board stm32f4: $(tail -5 build-small.txt)"
cat build-small.txt

# Left out means not linked: no symbol of the services the file leaves out.
for elf in $(awk '$2 ~ /\.elf$/ {print $2}' build-msd-*.txt build-hasel.txt build-small.txt); do
  syms=$(arm-none-eabi-nm -C "$elf" | grep -E 'IdentRun|Excitation::advance|SettingsService|SettingsStore|send_ident_sample|TransferReceiver::chunk' | head -3)
  [ -z "$syms" ] || say "$elf links a service its rig file leaves out: $syms"
done
# Smaller than hasel's board image with every service.
board_elf=$(grep -- "/nlsoft-stm32f4-hasel-min.elf\$" build-hasel.txt | awk '{print $2}')
full_elf=$(grep -- "/nlsoft-stm32f4-hasel-full.elf\$" build-full.txt | awk '{print $2}')
if [ -f "$board_elf" ] && [ -f "$full_elf" ]; then
  min=$(arm-none-eabi-size "$board_elf" | awk 'NR == 2 {print $1 + $2}')
  full=$(arm-none-eabi-size "$full_elf" | awk 'NR == 2 {print $1 + $2}')
  # The symbols the minimal image must not link are there with every service.
  arm-none-eabi-nm -C "$full_elf" | grep -q 'SettingsService' || say "the full image links no SettingsService: the symbol check proves nothing"
  echo "hasel on stm32f4: flash $min bytes with no service beyond the minimum, $full with every one"
  [ "$min" -lt "$full" ] || say "the minimal hasel image ($min bytes) is not smaller than the full one ($full)"
  # Issue #57's bound for the controller-only image (the goal is 24 kB:
  # docs/rig-file.md gives what fills the rest): a change that makes it
  # larger says so here.
  bound=47104
  [ "$min" -le "$bound" ] || say "the minimal hasel image ($min bytes) is above its bound ($bound)"
  # Nor does it link what neither its rig nor its services use: newlib's
  # fmodf (shared/remainder.hpp stands in), the servo USART, the flash
  # driver of saved settings, and the activations its model has none of
  # (compiled into its shape without model uploads: no fast exp table).
  unused='\<(fmodf|__ieee754_fmodf)$|ServoUsart|Flash<|kExp2Sixteenths'
  syms=$(arm-none-eabi-nm -C "$board_elf" | grep -E "$unused" | head -3)
  [ -z "$syms" ] || say "the minimal hasel image links what it does not use: $syms"
  # With every service (model uploads: any activation) the exp table is there: the check can fail.
  arm-none-eabi-nm -C "$full_elf" | grep -q kExp2Sixteenths || say "the full image has no exp table: the check proves nothing"
  small_elf=$(grep -- "/nlsoft-stm32f4-hasel-small.elf\$" build-small.txt | awk '{print $2}')
  small=$(arm-none-eabi-size "$small_elf" | awk 'NR == 2 {print $1 + $2}')
  echo "hasel on stm32f4: flash $small bytes with no service beyond the minimum, optimize = \"size\""
  [ -n "$small" ] && [ "$small" -lt "$min" ] || say "optimize = \"size\" ($small bytes) is not smaller than $min"
  arm-none-eabi-nm -C "$small_elf" | grep -q 'ShapedRollout' && say "the size-first image links the shape's own kernel"
else
  say "no hasel board images to compare: $(cat build-hasel.txt build-full.txt)"
fi

# A service the board cannot carry: refused at its line, nothing built.
cp msd-min.toml msd-settings.toml
sed -i 's/^features = \[\]$/features = ["settings"]/' msd-settings.toml
line=$(grep -n '^features' msd-settings.toml | cut -d: -f1)
if "$console" firmware build --rig msd-settings.toml --board mps2-an386 --out refused >refused.txt 2>&1; then
  say "mps2-an386 built an image with saved settings"
fi
grep -q "msd-settings.toml:$line: \[firmware\] features: 'settings': board mps2-an386 has nowhere to keep saved settings" refused.txt ||
  say "the refusal does not name the line: $(cat refused.txt)"
[ ! -e refused ] || say "a refused build left refused/"
built
