#!/usr/bin/env bash
# exchange.sh ACCELVIZ EXAMPLES_DIR MESH.obj: export and check round trips for every
# kind of structure (JSON and binary); a broken tree is refused with its node and
# exit 1; --json is JSON for autograders; the Python example's tree is valid.
set -eu
av=$1; examples=$2; mesh=$3
dir=$(mktemp -d); trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

for accel in "bvh" "bvh --bvh-width 4" "bvh --bvh-width 8" "kd" "grid"; do
  for ext in json avs; do
    # shellcheck disable=SC2086
    "$av" export builtin:teapot --accel $accel --out "$dir/t.$ext" >/dev/null
    out=$("$av" check builtin:teapot "$dir/t.$ext" --width 64 --height 48) || fail "$accel $ext: check failed: $out"
    grep -q "^valid" <<<"$out" || fail "$accel $ext: not valid: $out"
    # Our tree read back measures exactly as ours: the two columns agree.
    grep -E "^(SAH cost|nodes visited / ray|triangle tests / ray)" <<<"$out" |
      awk '$(NF-1) != $NF { bad = 1 } END { exit bad }' || fail "$accel $ext: columns differ: $out"
  done
done

# One child box moved out of its parent: exit 1, the node named.
"$av" export builtin:teapot --accel bvh --out "$dir/t.json" >/dev/null
python3 - "$dir/t.json" "$dir/broken.json" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["nodes"][5]["box"][4] += 100.0
json.dump(doc, open(sys.argv[2], "w"))
PY
set +e
out=$("$av" check builtin:teapot "$dir/broken.json"); rc=$?
json=$("$av" check builtin:teapot "$dir/broken.json" --json); json_rc=$?
set -e
echo "$out"
[ $rc -eq 1 ] || fail "a broken tree exited $rc"
grep -q "NOT VALID" <<<"$out" || fail "no NOT VALID"
grep -q "node 5's box sticks out of its parent's" <<<"$out" || fail "node 5 not named"
[ $json_rc -eq 1 ] || fail "--json on a broken tree exited $json_rc"
python3 -c 'import json,sys; d=json.load(sys.stdin); assert d["valid"] is False and any(p["node"]==5 for p in d["problems"])' <<<"$json" ||
  fail "--json does not name node 5"

# --hits: a traversal's answers (here ours, from trace) agree; a wrong one is listed with
# the trace command that steps it through the file's tree, and that command runs.
"$av" export builtin:teapot --accel bvh --out "$dir/t.json" >/dev/null
{
  echo "x,y,triangle,t"
  for p in 32,24 40,30 20,25 3,3; do
    "$av" trace builtin:teapot --pixel $p --width 64 --height 48 --json |
      python3 -c 'import json,sys; d=json.load(sys.stdin); r=d["result"]; print("%d,%d,%d,%r" % (d["pixel"][0], d["pixel"][1], r["tri"] if r["hit"] else -1, r.get("t", 0)))'
  done
} >"$dir/hits.csv"
cat "$dir/hits.csv"
out=$("$av" check builtin:teapot "$dir/t.json" --hits "$dir/hits.csv" --width 64 --height 48) || fail "our own hits: $out"
grep -q "4 pixels; 4 agree with brute force, 0 differ" <<<"$out" || fail "our own hits do not agree: $out"
sed 's/^40,30,\([0-9]*\),/40,30,7,/' "$dir/hits.csv" >"$dir/wrong.csv"
set +e
out=$("$av" check builtin:teapot "$dir/t.json" --hits "$dir/wrong.csv" --width 64 --height 48); rc=$?
set -e
echo "$out"
[ $rc -eq 1 ] || fail "a wrong hit exited $rc"
grep -q "pixel (40, 30): yours triangle 7" <<<"$out" || fail "the wrong pixel is not listed"
cmd=$(grep -m1 "accelviz trace" <<<"$out" | sed 's/^ *accelviz //')
[ -n "$cmd" ] || fail "no trace command"
# shellcheck disable=SC2086
"$av" $cmd | grep -q "^hit: triangle" || fail "the trace command did not step the ray: $cmd"

# The Python example: a median-split BVH, valid, with its figures beside ours.
python3 "$examples/median_bvh.py" "$mesh" "$dir/student.json"
out=$("$av" check "$mesh" "$dir/student.json" --json) || fail "the example's tree is not valid: $out"
python3 -c 'import json,sys; d=json.load(sys.stdin); assert d["valid"] and d["yours"]["mismatches"] == 0 and d["yours"]["sah_cost"] > 0' <<<"$out" ||
  fail "the example's figures: $out"
echo "ok"
