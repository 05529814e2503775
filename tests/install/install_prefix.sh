#!/usr/bin/env bash
# `cmake --install` into a prefix, which is then moved: copied to another
# folder and the first deleted, so a path of the first prefix compiled in
# would lead nowhere. Then check_prefix.sh runs the console from there.
#   install_prefix.sh BUILD_DIR SOURCE_DIR VERSION [check_prefix.sh flags...]
set -euo pipefail
build=$1 src=$2 version=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
start=$(date +%s%N)
# --strip, as the .deb is: a binary's debug information names the source
# files, which is no path the program uses.
cmake --install "$build" --prefix "$work/first" --strip >/dev/null
cp -a "$work/first" "$work/moved"
rm -rf "$work/first"
"$here/check_prefix.sh" "$work/moved" "$src" "$build" "$version" "$@"
echo "install and check: $(( ($(date +%s%N) - start) / 1000000 )) ms"
