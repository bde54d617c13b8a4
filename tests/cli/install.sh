#!/usr/bin/env bash
# install.sh BUILD_DIR: `cmake --install` into a temporary prefix, then the installed
# binary renders a shipped preset by name. The preset must come from the prefix
# (PREFIX/share/accelviz/presets), not from the source tree the binary was built in.
set -euo pipefail
build=$1
prefix=$(mktemp -d); trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
for f in bin/accelviz share/accelviz/presets/30-grid-stadium.json share/doc/accelviz/README.md \
         share/doc/accelviz/architecture.md; do
  [ -e "$prefix/$f" ] || { echo "FAIL: $f is not installed"; exit 1; }
done
cd "$prefix"  # nowhere near the source tree
err=$("$prefix/bin/accelviz" render --preset 30-grid-stadium --view raycast --width 96 --height 54 \
      --out "$prefix/stadium.png" 2>&1 >/dev/null) || { echo "FAIL: render: $err"; exit 1; }
echo "$err"
grep -qF "$prefix/share/accelviz/presets/30-grid-stadium.json" <<<"$err" ||
  { echo "FAIL: the preset was not taken from the prefix"; exit 1; }
[ -s "$prefix/stadium.png" ] || { echo "FAIL: no image"; exit 1; }
echo "installed into $prefix and rendered a preset from there: ok"
