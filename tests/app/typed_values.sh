#!/usr/bin/env bash
# Values and paths a user types, through the real console, as root: each
# impossible one refused where it enters (file:line, or the option's name),
# nothing stored; the database where the XDG rules put it, or a refusal that
# says why; a database or file that is not what it should be named with its
# fault.
#   typed_values.sh CONSOLE SOURCE_DIR
set -u
console=$1 src=$2
fail=0
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
export NLSOFT_RIGS=$src/rigs
say() { echo "FAIL: $*"; fail=1; }
# refused "pattern" args...: exit 2, the pattern in the output.
refused() {
  local pattern=$1
  shift
  out=$("$console" "$@" 2>&1)
  rc=$?
  [ $rc -eq 2 ] && grep -qF -- "$pattern" <<<"$out" || say "'$*' gave rc=$rc, not '$pattern': $out"
}
db_runs() { python3 -c "import sqlite3,sys; print(sqlite3.connect(sys.argv[1]).execute('select count(*) from runs').fetchone()[0])" "$1"; }

# The database's folder: XDG_DATA_HOME (absolute), else HOME, which must exist.
mkdir home
out=$(env -u XDG_DATA_HOME HOME=/nonexistent-home "$console" runs list 2>&1)
[ $? -eq 2 ] && grep -qF "HOME=/nonexistent-home does not exist; set XDG_DATA_HOME or HOME to a folder, or give --db FILE" <<<"$out" ||
  say "HOME=/nonexistent-home: $out"
[ -e /nonexistent-home ] && { say "/nonexistent-home was created"; rm -rf /nonexistent-home; }
out=$(env -u XDG_DATA_HOME -u HOME "$console" runs list 2>&1)
[ $? -eq 2 ] && grep -qF "HOME is not set" <<<"$out" || say "HOME unset: $out"
[ -e .local ] && say "HOME unset: ./.local was created"
# A relative XDG_DATA_HOME is ignored (the XDG rules), HOME then holds the database.
printf 'run 200ms label=first\n' >first.nls
env XDG_DATA_HOME=relative HOME="$work/home" timeout 60 "$console" --sim msd --sim-fast --script first.nls >first.txt 2>&1 ||
  say "a run with HOME=$work/home: $(cat first.txt)"
db=$work/home/.local/share/nlsoft/runs.db
grep -qF "recording to $db" first.txt || say "the console does not say where the database is: $(cat first.txt)"
[ -f "$db" ] && [ "$(db_runs "$db")" = 1 ] || say "no run in $db"
[ -e relative ] && say "the relative XDG_DATA_HOME was used"

# A label is data in the plot's gnuplot script too (gnuplot runs `...` in double quotes).
label=$'it\'s `touch PWNED` $(touch PWNED) "q" \\'
"$console" runs label 1 "$label" --db "$db" >/dev/null 2>&1 || say "runs label"
if command -v gnuplot >/dev/null; then
  "$console" runs plot 1 --svg plot.svg --db "$db" >plot.txt 2>&1 || say "runs plot: $(cat plot.txt)"
  [ -e PWNED ] && say "a run's label ran as a command in runs plot"
  grep -qF "it&apos;s \`touch PWNED\`" plot.svg || grep -qF "it's \`touch PWNED\`" plot.svg ||
    say "the label is not in the plot as typed"
fi

# A database that is a folder, or damaged, is named with what is wrong.
mkdir folder.db
refused "database folder.db is a folder, not a database file" runs list --db folder.db
cp "$db" damaged.db
python3 - damaged.db <<'EOF'
import sys
b = open(sys.argv[1], "rb").read()
open(sys.argv[1], "wb").write(b.replace(b"label TEXT", b"lbbel TEXT", 1))
EOF
refused "database damaged.db is not an nlsoft recording database: its table 'runs' is not the one schema v7 defines" runs list --db damaged.db

# Impossible values in a script: refused at their line before anything runs.
# script LINES: the console's output running them against the simulator (exit $rc).
script() {
  printf "$1" >bad.nls
  out=$(env HOME="$work/home" timeout 60 "$console" --sim msd --sim-fast --script bad.nls 2>&1)
  rc=$?
}
script 'run 1e30h\n'
[ $rc -eq 2 ] && grep -qF "bad.nls:1: '1e30h': a duration is at most 30 days (720h)" <<<"$out" || say "run 1e30h: $out"
script 'set r 1e-400\nrun 100ms\n'
[ $rc -eq 2 ] && grep -qF "bad.nls:1: r: '1e-400' underflows a float32" <<<"$out" || say "set r 1e-400: $out"
printf 'y0\n0.5\n1e308\n' >ref.csv
script 'ref load ref.csv\nrun 100ms\n'
[ $rc -eq 2 ] && grep -qF "ref.csv:3: '1e308' is beyond a float's range" <<<"$out" || say "ref load of 1e308: exit $rc: $out"
[ "$(db_runs "$db")" = 1 ] || say "bad.nls recorded a run"

# Options and rig keys.
refused "--steps: Value -5 not in range 1 to 100000000" simulate --rig msd --steps -5
sed 's/^rate_hz = .*/rate_hz = 1e308/' "$src/rigs/msd.toml" >fast.toml
refused "fast.toml:$(grep -n '^rate_hz' fast.toml | cut -d: -f1): rate_hz: must be in [0.001, 100000] Hz, not 1e+308" \
  rig check fast.toml
refused "fast.toml:$(grep -n '^rate_hz' fast.toml | cut -d: -f1): rate_hz" simulate --rig fast.toml

# Training data: each fault at its file:line, no model written.
"$console" runs export 1 --csv run.csv --db "$db" >/dev/null 2>&1 || say "runs export 1"
python3 - run.csv <<'EOF'
import sys
lines = open(sys.argv[1]).read().split("\n")
head, rows = lines[0], [l for l in lines[1:] if l]
cols = head.split(",")
def put(name, text):
    open(name, "w").write(text)
# A BOM before the header: read as the header it is (trained on below).
put("bom.csv", "\ufeff" + "\n".join([head] + rows) + "\n")
# u0 twice.
put("dup.csv", "\n".join([head + ",u0"] + [r + "," + r.split(",")[cols.index("u0")] for r in rows]) + "\n")
# A measured value of 1e308 on data line 5 (file line 6).
r = rows[4].split(","); r[cols.index("y_true0")] = "1e308"
put("huge.csv", "\n".join([head] + rows[:4] + [",".join(r)] + rows[5:]) + "\n")
# Rows 6 and 7 (file lines 7, 8) swapped: k and the clock go back.
put("back.csv", "\n".join([head] + rows[:5] + [rows[6], rows[5]] + rows[7:]) + "\n")
EOF
train() { "$console" train --rig msd --data "$1" --out "$2" --epochs 1 2>&1; }
out=$(train dup.csv dup.nlsm); [ $? -eq 2 ] && grep -qF "dup.csv:1: columns" <<<"$out" && grep -qF "are both named 'u0'" <<<"$out" ||
  say "duplicated u0: $out"
out=$(train huge.csv huge.nlsm); [ $? -eq 2 ] && grep -qF "huge.csv:6: column" <<<"$out" &&
  grep -qF "'1e308' is beyond a float's range" <<<"$out" || say "1e308: $out"
out=$(train back.csv back.nlsm); [ $? -eq 2 ] && grep -qF "back.csv:8: k " <<<"$out" || say "time going back: $out"
for m in dup huge back; do [ -e $m.nlsm ] && say "$m.nlsm was written"; done
out=$(train bom.csv bom.nlsm) || say "a BOM: $out"

# A capture of impossible values, or that cannot be placed, changes no run.
python3 - >cap.csv <<'EOF'
print("time,y0")
for i in range(200): print("%g,%g" % (i * 0.001, 1e308 if i == 50 else 0.1 * i))
EOF
refused "cap.csv:52: column 2 ('y0'): '1e+308' is beyond a float's range" runs merge-y 1 cap.csv --db "$db"
python3 - >flat.csv <<'EOF'
print("time,y0")
for i in range(400): print("%.3f,0.25" % (1e6 + i * 0.001))
EOF
refused "flat.csv: every output is constant over the capture" runs merge-y 1 flat.csv --db "$db"
exit $fail
