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
# On the small part (mps2-an385, 64 kB of flash): hasel's and msd's minimum
# fit, hasel with every service is refused by how much it overflows.
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

# The small part (mps2-an385: a Cortex-M3 without FPU in 64 kB of flash and
# 20 kB of RAM): hasel's minimum fits, as does msd's; hasel with every
# service does not, and the refusal says by how much and what to leave out.
"$console" firmware build --rig hasel-min.toml --board mps2-an385 --hil >build-m3.txt 2>&1 ||
  say "firmware build --rig hasel-min.toml --board mps2-an385 --hil: $(tail -5 build-m3.txt)"
cat build-m3.txt
m3_elf=$(grep -- "/nlsoft-m3-hasel-min-hil.elf\$" build-m3.txt | awk '{print $2}')
if [ -f "$m3_elf" ]; then
  arm-none-eabi-readelf -A "$m3_elf" | grep -q "Tag_CPU_name: \"7-M\"\|Tag_CPU_arch: v7\$" ||
    say "the an385 image is not built for the Cortex-M3: $(arm-none-eabi-readelf -A "$m3_elf" | head -8)"
  arm-none-eabi-readelf -A "$m3_elf" | grep -q "Tag_FP_arch" && say "the an385 image uses an FPU the Cortex-M3 lacks"
  read -r m3_text m3_data m3_bss <<<"$(arm-none-eabi-size "$m3_elf" | awk 'NR == 2 {print $1, $2, $3}')"
  echo "hasel on mps2-an385 (Cortex-M3, soft float): flash $((m3_text + m3_data)) bytes, RAM $((m3_data + m3_bss)) bytes"
  [ $((m3_text + m3_data)) -le 65536 ] && [ $((m3_data + m3_bss)) -le 20480 ] || say "the an385 image is larger than its part"
else
  say "no an385 hasel image: $(cat build-m3.txt)"
fi
"$console" firmware build --rig msd-min.toml --board mps2-an385 >build-m3-msd.txt 2>&1 ||
  say "firmware build --rig msd-min.toml --board mps2-an385: $(tail -5 build-m3-msd.txt)"
if "$console" firmware build --rig hasel-full.toml --board mps2-an385 --hil >m3-full.txt 2>&1; then
  say "hasel with every service built for a 64 kB part: $(cat m3-full.txt)"
fi
grep -q "rig 'hasel-full' (hasel-full.toml) does not fit board mps2-an385's memory .*: region .FLASH' overflowed by [0-9]* bytes; .*features = \[\]" m3-full.txt ||
  say "the an385's refusal of hasel with every service: $(cat m3-full.txt)"

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
