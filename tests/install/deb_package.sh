#!/usr/bin/env bash
# The .deb: cpack builds it, its control fields and file list are checked
# (dpkg-deb), and it is unpacked into a folder, not installed on this
# machine, and the console run from there as from an install prefix
# (check_prefix.sh).
#   deb_package.sh BUILD_DIR SOURCE_DIR VERSION [check_prefix.sh flags...]
set -euo pipefail
build=$1 src=$2 version=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
fail() { echo "FAIL: $*" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/pkg" >"$work/cpack.log" 2>&1 || {
  cat "$work/cpack.log"
  fail "cpack"
}
arch=$(dpkg --print-architecture)
deb=$work/pkg/nlsoft_${version}_${arch}.deb
[ -f "$deb" ] || fail "no $deb; cpack made: $(ls "$work/pkg")"
echo "$(basename "$deb"): $(stat -c %s "$deb") bytes"

field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Package)" = nlsoft ] || fail "Package: $(field Package)"
[ "$(field Version)" = "$version" ] || fail "Version: $(field Version), the project is $version"
[ "$(field Architecture)" = "$arch" ] || fail "Architecture: $(field Architecture)"
depends=$(field Depends)
for lib in libc6 libstdc++6 libncursesw6 libsqlite3-0 libhdf5 libfmt; do
  [[ $depends == *"$lib"* ]] || fail "Depends lacks $lib: $depends"
done
[[ $(field Recommends) == *qemu-system-arm* && $(field Recommends) == *gnuplot-nox* ]] ||
  fail "Recommends: $(field Recommends)"
[[ $(field Suggests) == *openocd* ]] || fail "Suggests: $(field Suggests)"
dpkg-deb -I "$deb"

dpkg-deb -c "$deb" | awk '{print $NF}' >"$work/files"
for f in ./usr/bin/nlsoft-console ./usr/libexec/nlsoft/nlsoft-firmware-sim ./usr/share/nlsoft/models/hasel.nlsm \
  ./usr/share/nlsoft/rigs/hasel.toml \
  ./usr/share/doc/nlsoft/README.md ./usr/share/bash-completion/completions/nlsoft-console; do
  grep -qxF "$f" "$work/files" || fail "$f not in the package"
done
# Nothing outside /usr, and no build-tree leftovers.
grep -v '^\./usr/' "$work/files" | grep -vx '\./' && fail "files outside /usr"
grep -E '\.(map|noheap)$|CMakeFiles' "$work/files" && fail "build leftovers in the package"

dpkg-deb -x "$deb" "$work/root"
"$here/check_prefix.sh" "$work/root/usr" "$src" "$build" "$version" "$@"
