#!/usr/bin/env bash
# Outputs read on the board (the qemu part; adc_outputs_build.sh built the
# plain stm32f4 image of a rig file whose outputs are on ADC1_IN8, gain 2,
# offset 1.5, and IN9, offset -2.5): QEMU's netduinoplus2 boots it as a user
# would boot a board (its USART2 on a pty). An identification run over that
# port records y_true (sent only by an image that says it measures y) on
# every sample, as the HAL scales it: QEMU models ADC1 but no DMA
# controller, so the scan's buffer stays at 0 V and y_true is each output's
# offset, in output order (1.5, -2.5) - the ADC's values themselves only a
# board shows.
# Exit 77 (ctest: skipped) without arm-none-eabi-g++ or qemu-system-arm.
#   adc_outputs_qemu.sh CONSOLE STAGE_FOLDER
set -u
console=$1
stage=$2 part=qemu
. "$(dirname "$0")/rig_image_test_prelude.sh"

elf=$(grep -- "/nlsoft-stm32f4-stage.elf\$" build.txt | awk '{print $2}')
[ -f "$elf" ] || { echo "FAIL: no board image in build.txt: $(cat build.txt)"; exit 1; }
boot_qemu netduinoplus2 "$elf" || { echo "FAIL: QEMU gave no pty: $(cat qemu.out)"; exit 1; }

timeout 120 "$console" ident "$port" --rig my.toml --signal prbs --duration 5s --db runs.db >ident.txt 2>&1 ||
  say "ident: $(cat ident.txt)"
cat ident.txt
"$console" runs export 1 --csv run.csv --db runs.db >log.txt 2>&1 || { say "runs export: $(cat log.txt)"; exit 1; }
python3 - run.csv <<'EOF' || say "y_true is not the outputs' ADC reading"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(len(rows), "samples; y_true of the first:", rows[0]["y_true0"] if rows else None, rows[0]["y_true1"] if rows else None)
bad = [r["k"] for r in rows if r["y_true0"] == "" or r["y_true1"] == ""
       or float(r["y_true0"]) != 1.5 or float(r["y_true1"]) != -2.5]
if bad: print("samples without y_true = (1.5, -2.5):", bad[:5])
sys.exit(1 if bad or len(rows) < 40 else 0)
EOF
[ $fail -eq 0 ] && echo "outputs on the ADC: the stm32f4 image measures y and the run records it"
exit $fail
