#!/usr/bin/env bash
# `sdv diff --runs`: a run against itself is equal (exit 0); against the same scenario with one
# parameter changed it names the first divergent tick, the vehicle, and the first planning
# decision that changed (exit 1).
set -u
sdv=$1
root=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
sed 's/tree cut_in_driver(speed = 18 m\/s)/tree cut_in_driver(speed = 19 m\/s)/' "$root/examples/cut_in.sdv" > "$dir/changed.sdv"
"$sdv" run "$root/examples/cut_in.sdv" -o "$dir/a" --trace >/dev/null
"$sdv" run "$dir/changed.sdv" -o "$dir/b" --trace >/dev/null
"$sdv" diff --runs "$dir/a" "$dir/a" || { echo "FAIL: a run differs from itself"; exit 1; }
out=$("$sdv" diff --runs "$dir/a" "$dir/b")
code=$?
echo "$out"
[ $code -eq 1 ] || { echo "FAIL: exit $code"; exit 1; }
grep -q "first divergence at tick [0-9]* (t = .* s): v2" <<<"$out" || { echo "FAIL: no divergent tick for v2"; exit 1; }
grep -q "first differing decision at t = .* s, vehicle v2: maneuver keep: winning candidate" <<<"$out" || { echo "FAIL: no differing decision"; exit 1; }
echo "ok"
