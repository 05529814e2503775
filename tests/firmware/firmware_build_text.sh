#!/usr/bin/env bash
# What a user types stays data in what `firmware build` generates (the rig
# header in C++, image.cmake, the build's command lines). Every string-valued
# key of a rig file, given text holding quotes, a backslash, a newline, '#',
# $(...), '*/', '")' and a bracket's close, is refused by `rig check` and by
# `firmware build` at its file:line and key, or, when the key takes such text,
# built; the paths of --rig and --model holding the same text build an image
# whose generated sources read them back byte for byte, and whose embedded
# model is that file's; an --out holding it is refused by name; and no file
# appears outside --out (none named PWNED, which the text would create if run).
# Exit 77 (ctest: skipped) without arm-none-eabi-g++.
#   firmware_build_text.sh CONSOLE SOURCE_DIR WORK_FOLDER
set -u
console=$1 src=$2 work=$3
command -v arm-none-eabi-g++ >/dev/null || { echo "SKIP: arm-none-eabi-g++ is not installed"; exit 77; }
rm -rf "$work" && mkdir -p "$work/logs" "$work/home" || exit 1
cd "$work" || exit 1
export HOME=$work/home XDG_CACHE_HOME=$work/cache XDG_DATA_HOME=$work/data
fail=0
say() { echo "FAIL: $*"; fail=1; }
logs=$work/logs

# The text, one line and several.
line=$'q"b\\s#h$(touch PWNED)`touch PWNED`*/")x]=]]'
lines="$line"$'\n'"execute_process(COMMAND touch PWNED)"$'\n'"#error injected"

# every_key TEXT: one rig file per string-valued key, the key holding TEXT
# (tables/keys.txt: file, key label, line of the key, key name).
every_key() {
  python3 - "$src" "$1" "$2" <<'EOF'
import json, os, sys
src, text, out = sys.argv[1], sys.argv[2], sys.argv[3]
bases = {"msd": open(os.path.join(src, "rigs/msd.toml")).read(),
         "stage": open(os.path.join(src, "tests/app/rig/stage.toml")).read()}
# (base, table header, which one of that table, key)
keys = [("msd", None, 0, "name"), ("msd", None, 0, "description"), ("msd", None, 0, "board"),
        ("msd", "[[input]]", 0, "name"), ("msd", "[[input]]", 0, "unit"), ("msd", "[[input]]", 0, "pwm"),
        ("msd", "[[output]]", 0, "name"), ("msd", "[[output]]", 0, "unit"), ("msd", "[[output]]", 0, "source"),
        ("stage", "[[sensor]]", 1, "name"), ("stage", "[[sensor]]", 1, "source"),
        ("msd", "[controller]", 0, "mode"), ("msd", "[controller]", 0, "feedback"),
        ("msd", "[model]", 0, "file"), ("msd", "[[model.layer]]", 0, "kind"),
        ("msd", "[[model.layer]]", 0, "activation"), ("msd", "[plant]", 0, "kind"),
        ("stage", "[[plant.actuator]]", 2, "shape"), ("msd", "[reference]", 0, "kind")]
os.makedirs(out, exist_ok=True)
rows = []
for n, (base, table, which, key) in enumerate(keys):
    lines = bases[base].split("\n")
    current, seen, at = None, {}, None
    for i, l in enumerate(lines):
        s = l.split("#")[0].strip()
        if s.startswith("["):
            current = s
            seen[s] = seen.get(s, -1) + 1
            continue
        if current == table and (table is None or seen[table] == which) and s.split("=")[0].strip() == key:
            at = i
            break
    assert at is not None, (table, key)
    # A TOML basic string: JSON's escapes are TOML's.
    lines[at] = key + " = " + json.dumps(text, ensure_ascii=False)
    path = os.path.join(out, "k%02d.toml" % n)
    open(path, "w").write("\n".join(lines))
    rows.append("%s\t%s %s\t%d\t%s" % (path, table or "", key, at + 1, key))
open(os.path.join(out, "keys.txt"), "w").write("\n".join(rows) + "\n")
EOF
}

# Each key, both texts: `rig check` refuses at the key's file:line naming
# it, or accepts; `firmware build` refuses the same way (before building).
accepted=""
for which in line lines; do
  every_key "${!which}" "$work/keys-$which" || { echo "FAIL: cannot write the rig files"; exit 1; }
  while IFS=$'\t' read -r file label at key; do
    "$console" rig check "$file" >"$logs/check.txt" 2>&1
    rc=$?
    if [ $rc -eq 0 ]; then
      accepted="$accepted $label($which)"
      continue
    fi
    [ $rc -eq 2 ] || say "rig check, $label ($which): exit $rc: $(cat "$logs/check.txt")"
    grep -qF "$file:$at: " "$logs/check.txt" && grep -qF "$key" "$logs/check.txt" ||
      say "rig check, $label ($which): not refused at $file:$at naming $key: $(cat "$logs/check.txt")"
    "$console" firmware build --rig "$file" --board stm32f4 --out "$work/refused" >"$logs/build.txt" 2>&1
    rc=$?
    [ $rc -eq 2 ] && grep -qF "$file:$at: " "$logs/build.txt" ||
      say "firmware build, $label ($which): exit $rc, not refused at $file:$at: $(cat "$logs/build.txt")"
    [ -e "$work/refused" ] && say "firmware build, $label ($which): made $work/refused though it refused the rig"
  done <"$work/keys-$which/keys.txt"
done
echo "accepted as text:$accepted"
# Only one line of text, and only where text is shown, not where it names something.
for ok in "[[input]] unit(line)" "[[output]] unit(line)" " description(line)"; do
  case "$accepted" in *"$ok"*) ;; *) say "$ok refused: a unit or description is text" ;; esac
done
for k in $accepted; do
  case "$k" in *"(lines)") say "$k accepted a newline" ;; esac
done

# --rig and --model at paths holding the text, a description and a unit
# holding its one-line form: built, and read back byte for byte.
rigdir="$work/r$lines" modeldir="$work/m$lines"
rig="$rigdir/r$line.toml" model="$modeldir/m$line.nlsm"
mkdir -p "$(dirname "$rig")" "$(dirname "$model")" || exit 1
python3 - "$src/rigs/msd.toml" "$rig" "$line" <<'EOF'
import json, sys
text = open(sys.argv[1]).read().replace('name = "msd"', 'name = "text-msd"', 1)
text = text.replace('unit = "m"', "unit = " + json.dumps(sys.argv[3]), 1)
text = text.replace('description = ', "description = " + json.dumps(sys.argv[3]) + " #", 1)
open(sys.argv[2], "w").write(text)
EOF
cp "$src/app/models/msd.nlsm" "$model" || exit 1
touch "$logs/stamp"
out=$work/out
if "$console" firmware build --rig "$rig" --board mps2-an386 --model "$model" --out "$out" >"$logs/built.txt" 2>&1; then
  cat "$logs/built.txt"
  elf=$out/nlsoft-m4-text-msd-hil.elf
  [ -f "$elf" ] || say "no $elf: $(ls -a "$out")"
  header=$out/.rig/text-msd/nlsoft_rig.hpp
  # The rig file's path, from the C++ string literal in the header's first line.
  python3 - "$header" "$rig" <<'EOF' || say "the header does not name the rig file byte for byte: $(head -1 "$header")"
import sys
first = open(sys.argv[1], "rb").read().split(b"\n")[0].decode("ascii")
lit = first[first.index('"') + 1:]
out, i = bytearray(), 0
while lit[i] != '"':
    if lit[i] == "\\":
        if lit[i + 1] in "01234567":
            out.append(int(lit[i + 1:i + 4], 8)); i += 4
        else:
            out += lit[i + 1].encode(); i += 2
    else:
        out += lit[i].encode(); i += 1
sys.exit(0 if bytes(out) == sys.argv[2].encode() else 1)
EOF
  # The model's path, as CMake reads image.cmake.
  printf 'include("%s")\nfile(WRITE "%s" "${NLSOFT_IMAGE_MODEL_SOURCE}")\n' "$out/.rig/text-msd/image.cmake" \
    "$logs/model-source.txt" >"$logs/read.cmake"
  cmake -P "$logs/read.cmake" >"$logs/cmake.txt" 2>&1 || say "cmake cannot read image.cmake: $(cat "$logs/cmake.txt")"
  [ "$(cat "$logs/model-source.txt"; echo .)" = "$model." ] ||
    say "image.cmake does not name the model byte for byte: $(cat "$logs/model-source.txt")"
  # The model embedded is that file's model.
  size=$(arm-none-eabi-nm -S "$elf" | python3 -c "
import sys
s = {l.split()[-1]: int(l.split()[0], 16) for l in sys.stdin if l.strip()}
print(s['nlsoft_model_end'] - s['nlsoft_model_begin'])")
  [ "$size" = "$(stat -c %s "$out/model.nlsm")" ] && cmp -s -n "$size" "$out/model.nlsm" "$model" ||
    say "the image embeds $size bytes, not the model of $model"
else
  say "firmware build with the text in --rig's and --model's paths: $(cat "$logs/built.txt")"
fi
# Nothing outside --out, nothing run.
outside=$(find "$work" -mindepth 1 -newer "$logs/stamp" -not -path "$out" -not -path "$out/*" -not -path "$logs" \
  -not -path "$logs/*" -print)
[ -z "$outside" ] || say "files outside --out: $outside"
pwned=$(find "$work" -name PWNED)
[ -z "$pwned" ] || say "the text ran as code: $pwned"

# An --out holding the text: refused by name, nothing made.
bad_out="$work/o$lines"
"$console" firmware build --rig "$rig" --board mps2-an386 --model "$model" --out "$bad_out" >"$logs/out.txt" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -q -- "--out '" "$logs/out.txt" || say "--out with the text: exit $rc: $(cat "$logs/out.txt")"
[ -e "$bad_out" ] && say "--out with the text was created"
[ -e "$work/o$line" ] && say "a part of --out's text was created"
exit $fail
