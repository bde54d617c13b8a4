#!/usr/bin/env bash
# expect.sh fail|ok "TEXT" -- COMMAND...
# Runs COMMAND; checks that it failed (non-zero exit) or succeeded, that its
# output (stdout + stderr) contains TEXT, that it did not crash (no signal),
# and that an error is one line (on stderr; stdout may have progress before it).
set -u
mode=$1; text=$2; shift 2; [ "$1" = "--" ] && shift
err_file=$(mktemp); trap 'rm -f "$err_file"' EXIT
stdout=$("$@" 2>"$err_file"); rc=$?; stderr=$(cat "$err_file")
out=$(printf '%s\n%s' "$stdout" "$stderr")
echo "$ $*"; echo "$out"; echo "exit code: $rc"
if [ $rc -ge 128 ]; then echo "FAIL: killed by signal $((rc - 128))"; exit 1; fi
if [ "$mode" = fail ] && [ $rc -eq 0 ]; then echo "FAIL: expected a non-zero exit"; exit 1; fi
if [ "$mode" = ok ] && [ $rc -ne 0 ]; then echo "FAIL: expected success"; exit 1; fi
if ! grep -qF -- "$text" <<<"$out"; then echo "FAIL: output does not contain '$text'"; exit 1; fi
if [ "$mode" = fail ] && [ "$(grep -c . <<<"$stderr")" -gt 1 ]; then echo "FAIL: the error is more than one line"; exit 1; fi
if [ "$mode" = fail ] && [ "$(grep -c . <<<"$out")" -gt 3 ]; then echo "FAIL: the output around the error is not short"; exit 1; fi
exit 0
