#!/usr/bin/env bash
# The cut-in's expectations hold for the cut-in itself (SPEC §3.10): with the cut-in removed
# from v2's tree (a copy of examples/cut_in.sdv in which v2 only drives on), v2 still passes
# the ego alongside in the next lane, and `sdv run` must then exit 1 on the same-lane bumper gap.
set -u
sdv=$1
src=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$sdv" run "$src/examples/cut_in.sdv" -o "$dir/original" >"$dir/original.txt" || { cat "$dir/original.txt"; echo "the cut-in example fails"; exit 1; }
# The mutation: the fallback of cut_in_driver keeps only its plain driving.
sed '/subtree std\.cut_in(/d' "$src/examples/cut_in.sdv" > "$dir/no_cut_in.sdv"
if cmp -s "$src/examples/cut_in.sdv" "$dir/no_cut_in.sdv" || grep -q 'std\.cut_in(' "$dir/no_cut_in.sdv"; then
    echo "the mutation did not remove the cut-in"; exit 1
fi
"$sdv" run "$dir/no_cut_in.sdv" -o "$dir/mutant" -Wno-unused-import >"$dir/mutant.txt" 2>"$dir/mutant.err"
code=$?
cat "$dir/mutant.txt"
[ "$code" = 1 ] || { echo "without the cut-in, sdv run exits $code, expected 1"; cat "$dir/mutant.err"; exit 1; }
grep -q '^  FAIL  expect min_gap(ego, v2)' "$dir/mutant.txt" || { echo "no failing min_gap expectation"; exit 1; }
python3 - "$dir" <<'PY'
import json, sys
d = sys.argv[1]
orig = json.load(open(f"{d}/original/summary.json"))
mut = json.load(open(f"{d}/mutant/summary.json"))
o, m = orig["metrics"]["pairs"][0], mut["metrics"]["pairs"][0]
# v2 still passes alongside (a small outline clearance) but never drives in the ego's lane.
assert m["min_clearance"] is not None and m["min_clearance"] < 5, m
assert m["min_gap"] is None, m
assert o["min_gap"] is not None, o
failed = [e for e in mut["expectations"] if not e["passed"]]
assert failed and all(p["metric"] == "min_gap" for e in failed for p in e["parts"] if not p["holds"]), failed
print(f"cut-in: same-lane gap {o['min_gap']} m; without it: none (outline clearance {m['min_clearance']} m): fails as it should")
PY
