#!/usr/bin/env bash
# progress.sh ACCELVIZ: long steps print a line on stderr when they pass the threshold
# and one when they end; --quiet prints none; quick steps print none.
set -eu
av=$1
dir=$(mktemp -d); trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
run() { "$av" render builtin:teapot --width 16 --height 16 --out "$dir/t.png" "$@" 2>"$dir/err" >/dev/null; cat "$dir/err"; }

err=$(ACCELVIZ_PROGRESS_AFTER_MS=0 run)
echo "$err"
grep -qF "accelviz render: loading builtin:teapot ..." <<<"$err" || fail "no line when the load passed the threshold"
grep -qE "^accelviz render: loading builtin:teapot: [0-9.]+ s$" <<<"$err" || fail "no line when the load ended"
grep -qE "^accelviz render: building bvh: [0-9.]+ s$" <<<"$err" || fail "no line when the build ended"
progress_lines() { grep -E "^accelviz render: (loading|building) " || true; }
[ -z "$(ACCELVIZ_PROGRESS_AFTER_MS=0 run --quiet | progress_lines)" ] || fail "--quiet printed progress"
[ -z "$(run | progress_lines)" ] || fail "a step under two seconds printed progress"
echo "ok"
