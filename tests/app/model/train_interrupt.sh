#!/usr/bin/env bash
# Ctrl-C during `train` keeps the best model so far: SIGINT once the
# simulation objective's L-BFGS reports, then the model file is written,
# exit 0, and train says it was stopped; `model info` reads the file.
#   train_interrupt.sh CONSOLE
set -u
console=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
"$console" dataset --rig hasel --out hasel.csv --steps 40000 >/dev/null || { echo "FAIL: dataset"; exit 1; }
"$console" train --rig hasel --data hasel.csv --out m.nlsm >out.txt 2>err.txt &
pid=$!
for _ in $(seq 600); do
  grep -q "L-BFGS" err.txt && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.1
done
grep -q "L-BFGS" err.txt || { cat out.txt err.txt; echo "FAIL: no L-BFGS progress to interrupt"; exit 1; }
kill -INT "$pid"
wait "$pid"
rc=$?
[ "$rc" = 0 ] || { cat out.txt err.txt; echo "FAIL: train exited $rc after Ctrl-C"; exit 1; }
grep -q "stopped (Ctrl-C): keeping the best model so far" out.txt || { cat out.txt; echo "FAIL: no word of the stop"; exit 1; }
"$console" model info m.nlsm >info.txt || { echo "FAIL: the model written after Ctrl-C does not read"; exit 1; }
echo "interrupted during L-BFGS: $(grep -c . out.txt) lines of report, model written"
