#!/usr/bin/env bash
# cache.sh ACCELVIZ: the mesh cache from the command line. The first load of an OBJ
# writes a copy under $XDG_CACHE_HOME/accelviz, later loads give the same answers,
# a damaged copy is replaced, and --no-cache writes nothing.
set -eu
av=$1
dir=$(mktemp -d); trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\n' > "$dir/corner.obj"
hits() { XDG_CACHE_HOME=$1 "$av" bench "$dir/corner.obj" "${@:2}" --width 32 --height 24 --repeat 1 --json |
           python3 -c 'import json,sys; print(json.load(sys.stdin)["hit_count"])'; }

first=$(hits "$dir/cache")
copy=$(ls "$dir"/cache/accelviz/*.mesh) || fail "no copy was written"
echo "first load: $first hits; copy $copy"
[ "$(hits "$dir/cache")" = "$first" ] || fail "the second load (from the copy) answers differently"
printf 'not a mesh' > "$copy"
[ "$(hits "$dir/cache")" = "$first" ] || fail "a damaged copy changed the answer"
[ "$(stat -c %s "$copy")" -gt 10 ] || fail "the damaged copy was not replaced"
[ "$(hits "$dir/none" --no-cache)" = "$first" ] || fail "--no-cache answers differently"
[ ! -e "$dir/none" ] || fail "--no-cache wrote $(ls -R "$dir/none")"
echo "ok"
