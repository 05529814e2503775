#!/usr/bin/env bash
# The README's opening says where `bash cmake/dev build` leaves the console
# (it is not on PATH): the path it names must be where the build puts the
# binary and what `bash cmake/dev demo` runs.
# usage: readme_console_path.sh SOURCE_DIR CONSOLE_BINARY BUILD_DIR
set -u
root=$1 console=$2 build=$3
rel=${console#"$build"/}
fail=0
opening=$(sed '/^## /q' "$root/README.md")
grep -qF "build/$rel" <<<"$opening" ||
  { echo "FAIL: the README's opening does not name build/$rel, where the console is built"; fail=1; }
grep -qF "\"\$build/$rel\"" "$root/cmake/dev" ||
  { echo "FAIL: cmake/dev demo does not run \$build/$rel"; fail=1; }
grep -qF "bash cmake/dev demo ARGS" <<<"$opening" ||
  { echo "FAIL: the README's opening does not say how bash cmake/dev demo runs the console"; fail=1; }
[ $fail -eq 0 ] && echo "README names build/$rel, the console cmake/dev builds and runs"
exit $fail
