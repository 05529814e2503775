#!/usr/bin/env bash
# Outputs read on the board (the build part; adc_outputs_qemu.sh boots
# it): a rig file whose every [[output]] has source = "adc"
# (tests/app/rig/stage.toml with x on ADC1_IN8, gain 2,
# offset 1.5, and y on IN9, offset -2.5; no [plant], so only the board's
# image, with the shape of a small network) builds the plain stm32f4 image
# (`firmware build --rig --board stm32f4`) whose generated header reads both
# outputs.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   adc_outputs_build.sh CONSOLE RIG_FILE STAGE_FOLDER
set -u
console=$1
fixture=$2  # tests/app/rig/stage.toml
stage=$3 part=build
. "$(dirname "$0")/rig_image_test_prelude.sh"

python3 - "$fixture" <<'EOF' || exit 1
import sys
text = open(sys.argv[1]).read()
# No [plant]: the board's image only; its network's shape (no model file: the image waits for an upload).
text = text[:text.index("[plant]")] + ('[model]\n[[model.layer]]\nkind = "dense"\nunits = 8\nactivation = "tanh"\n\n'
                                      '[[model.layer]]\nkind = "dense"\nunits = 2\nactivation = "linear"\n')
text = text.replace('name = "x"\nunit = "mm"\nmin = -10.0\nmax = 10.0\nsource = "external"',
                    'name = "x"\nunit = "mm"\nmin = -10.0\nmax = 10.0\nsource = "adc"\nadc = 8\ngain = 2.0\noffset = 1.5')
text = text.replace('name = "y"\nunit = "mm"\nmin = -10.0\nmax = 10.0\nsource = "external"',
                    'name = "y"\nunit = "mm"\nmin = -10.0\nmax = 10.0\nsource = "adc"\nadc = 9\noffset = -2.5')
assert text.count('source = "adc"') == 7, "the fixture's outputs changed"
open("my.toml", "w").write(text)
EOF

"$console" firmware build --rig my.toml --board stm32f4 >build.txt 2>&1 || { cat build.txt; echo "FAIL: firmware build"; exit 1; }
cat build.txt
elf=$(grep -- "/nlsoft-stm32f4-stage.elf\$" build.txt | awk '{print $2}')
[ -f "$elf" ] || { echo "FAIL: no board image reported: $(cat build.txt)"; exit 1; }
grep -q "kRigOutputRows = 2;" "$(dirname "$elf")/.rig/stage/nlsoft_rig.hpp" ||
  say "the generated header reads no output: $(cat "$(dirname "$elf")/.rig/stage/nlsoft_rig.hpp")"
built
