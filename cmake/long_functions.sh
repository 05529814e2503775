#!/usr/bin/env bash
# The functions longer than LIMIT lines (default 100), longest first, as
# "lines file:line name": from a function's first line to its closing
# brace, by Universal Ctags' end field. A lambda counts within the function
# that holds it, not apart. Issue #58 ("One value, one place") counts with it:
#   bash cmake/long_functions.sh [LIMIT]          the list
#   bash cmake/long_functions.sh 100 | wc -l      how many
# Needs universal-ctags (Debian's package of that name); neither the build
# nor the tests run this, so cmake/dev does not install it.
set -euo pipefail
limit=${1:-100}
cd "$(dirname "$0")/.."
if ! ctags --version 2>/dev/null | grep -q "Universal Ctags"; then
  echo "cmake/long_functions.sh: needs Universal Ctags (apt-get install universal-ctags)" >&2
  exit 2
fi
ctags -R --languages=C++ --kinds-C++=f --fields=+ne -f - app protocol shared host firmware 2>/dev/null |
  awk -F'\t' -v limit="$limit" '
    $1 ~ /^__anon/ { next }
    { line = ""; end = ""
      for (i = 4; i <= NF; i++) { if ($i ~ /^line:/) line = substr($i, 6); if ($i ~ /^end:/) end = substr($i, 5) }
      if (line != "" && end != "" && end - line + 1 > limit && !seen[$2 ":" line]++)
        print end - line + 1, $2 ":" line, $1 }' |
  sort -k1,1rn -k2
