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

# The Python example: a median-split BVH, valid, with its figures beside ours.
python3 "$examples/median_bvh.py" "$mesh" "$dir/student.json"
out=$("$av" check "$mesh" "$dir/student.json" --json) || fail "the example's tree is not valid: $out"
python3 -c 'import json,sys; d=json.load(sys.stdin); assert d["valid"] and d["yours"]["mismatches"] == 0 and d["yours"]["sah_cost"] > 0' <<<"$out" ||
  fail "the example's figures: $out"
echo "ok"
