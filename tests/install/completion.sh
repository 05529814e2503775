#!/usr/bin/env bash
# The bash completion script, as bash calls it: COMP_WORDS/COMP_CWORD set,
# the function run, COMPREPLY compared. Then its word lists against the
# console's own --help, so a command or option added to the console and not
# to the completion fails here.
#   completion.sh COMPLETION_FILE CONSOLE
set -uo pipefail
export LC_ALL=C  # one sort order for the expected lists
script=$(realpath "$1") console=$(realpath "$2")
failures=0

# complete WANT WORD...: the reply for the last word (the one being typed).
complete_is() {
  local want=$1
  shift
  local got
  got=$(
    cd "$work" || exit 1
    # shellcheck source=/dev/null
    source "$script"
    COMP_WORDS=("$@")
    COMP_CWORD=$((${#COMP_WORDS[@]} - 1))
    COMPREPLY=()
    _nlsoft_console
    printf '%s\n' "${COMPREPLY[@]}" | sort | tr '\n' ' ' | sed 's/ $//'
  )
  if [ "$got" != "$want" ]; then
    echo "FAIL: '$*' completes to '$got', want '$want'"
    failures=$((failures + 1))
    return 1
  fi
}

# The console on PATH, as installed: the completion asks it for the rigs.
PATH=$(dirname "$console"):$PATH
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
touch "$work/tune.nls" "$work/tune2.nls" "$work/runs.db" "$work/mocap.csv"

complete_is "conformance dataset firmware flash ident model ports rig runs simulate train tune" nlsoft-console ""
complete_is "chirp" nlsoft-console ident --signal c
complete_is "ports" nlsoft-console po
complete_is "--json" nlsoft-console ports --j
complete_is "simulate" nlsoft-console si
complete_is "hasel msd tendon" nlsoft-console --sim ""
complete_is "hasel" nlsoft-console --qemu h
complete_is "tendon" nlsoft-console simulate --rig t
complete_is "mps2-an385 mps2-an386 mps2-an500 stm32f4" nlsoft-console --qemu hasel --board ""
complete_is "stm32f4" nlsoft-console flash --board s
complete_is "tune.nls tune2.nls" nlsoft-console --sim hasel --script tu
complete_is "runs.db" nlsoft-console runs list --db r
complete_is "compare delete export label list merge-y plot replay show" nlsoft-console runs ""
complete_is "mocap.csv" nlsoft-console ident --sim hasel --y-from mo
complete_is "mocap.csv" nlsoft-console runs merge-y 1 mo
complete_is "--offset" nlsoft-console runs merge-y 1 mocap.csv --o
complete_is "label list" nlsoft-console runs l
complete_is "compare" nlsoft-console --db runs.db runs c
complete_is "--json" nlsoft-console runs show 12 --j
complete_is "eval fit import info" nlsoft-console model ""
complete_is "build header" nlsoft-console firmware ""
complete_is "check list" nlsoft-console rig ""
complete_is "hasel" nlsoft-console rig check ha
complete_is "--json" nlsoft-console rig check hasel --j
complete_is "Lambda=" nlsoft-console simulate --set La
complete_is "N1= N= Nc=" nlsoft-console simulate --set N
complete_is "nr_max_iter= nr_tol=" nlsoft-console simulate --set nr
complete_is "u_max= u_min=" nlsoft-console simulate --set u_
complete_is "safe_state=" nlsoft-console simulate --set sa
complete_is "Q=" nlsoft-console tune --sim hasel --param Q
complete_is "neldermead" nlsoft-console tune --method n
complete_is "stm32f4" nlsoft-console tune --qemu hasel --board s
complete_is "watchdog_ms=" nlsoft-console simulate --set w
complete_is "infinity" nlsoft-console simulate --reference inf
complete_is "exact fd" nlsoft-console simulate --mode ""
complete_is "--sim --sim-fast --sim-rate --sim-settings" nlsoft-console --sim
complete_is "--sim" nlsoft-console conformance --si

# A Tab starts the console only where a rig's name is typed: one process
# per Tab elsewhere made each Tab as slow as the console's start.
mkdir "$work/bin"
printf '#!/bin/sh\necho "$*" >>"%s/calls"\nexec "%s" "$@"\n' "$work" "$console" >"$work/bin/nlsoft-console"
chmod +x "$work/bin/nlsoft-console"
calls_for() {
  local want=$1
  shift
  : >"$work/calls"
  # In a subshell (PATH), so its failure is counted from its status.
  (PATH=$work/bin:$PATH && complete_is "$@") || failures=$((failures + 1))
  local n
  n=$(wc -l <"$work/calls")
  if [ "$n" -ne "$want" ]; then
    echo "FAIL: completing '${*:2}' ran the console $n times, want $want"
    failures=$((failures + 1))
  fi
}
calls_for 0 "compare delete export label list merge-y plot replay show" nlsoft-console runs ""
calls_for 0 "--json" nlsoft-console runs show 12 --j
calls_for 1 "hasel msd tendon" nlsoft-console --sim ""
calls_for 1 "hasel" nlsoft-console rig check ha

# Every parameter of the firmware's table, no more and no less.
params="Q Lambda s b r N N1 Nc eps u_min u_max nr_tol nr_max_iter mode feedback watchdog_ms safe_state"
want=$(for p in $params; do echo "$p="; done | sort | tr '\n' ' ' | sed 's/ $//')
complete_is "$want" nlsoft-console simulate --set ""

# The word lists against --help: each command's subcommands and options.
# CLI11 lists subcommands under "Subcommands:" at an indent of two, and
# options under "Options:" as "  --name", "  -h,--help" or "  --name,--alias".
help_words() {
  "$console" "$@" --help 2>&1 | awk '
    /^[^ ]/ { section = $0; next }
    section == "Subcommands:" && /^  [a-z]/ { print $1 }
    section == "Options:" && /^  +(-[a-z], *)?--/ {
      sub(/^ +(-[a-z], *)?/, ""); sub(/[ :=].*/, "")
      n = split($0, names, ","); for (i = 1; i <= n; i++) print names[i]  # aliases: --name,--alias
    }'
}
check_against_help() {
  local typed=("$@")
  local w got
  for w in $(help_words "${typed[@]:1}"); do
    got=$(
      source "$script"
      COMP_WORDS=("${typed[@]}" "$w")
      COMP_CWORD=$((${#COMP_WORDS[@]} - 1))
      COMPREPLY=()
      _nlsoft_console
      printf '%s\n' "${COMPREPLY[@]}"
    )
    if ! grep -qxF -- "$w" <<<"$got"; then
      echo "FAIL: '${typed[*]} --help' lists $w; the completion does not offer it"
      failures=$((failures + 1))
    fi
  done
}
check_against_help nlsoft-console
for c in simulate conformance flash firmware dataset train tune ident runs model ports rig; do check_against_help nlsoft-console "$c"; done
for c in list show export compare plot label delete merge-y replay; do check_against_help nlsoft-console runs "$c"; done
for c in import eval info fit; do check_against_help nlsoft-console model "$c"; done
for c in check list; do check_against_help nlsoft-console rig "$c"; done
check_against_help nlsoft-console firmware build
check_against_help nlsoft-console firmware header

[ "$(help_words | wc -l)" -gt 10 ] || { echo "FAIL: could not read the console's --help"; failures=$((failures + 1)); }
if [ $failures -gt 0 ]; then
  echo "$failures failure(s)"
  exit 1
fi
echo "ok: completion matches the console's --help"
