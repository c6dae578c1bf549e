#!/usr/bin/env bash
# The GeoScenario scenarios of shared/data/geoscenario/scenarios/test (path vehicles, path,
# trajectory and simulated pedestrians), end to end, each as tests/scenarios/geoscenario.sh does
# for the core scenarios:
#   1. `sdv run X.osm --gss-outputs` gives the reference's outcome (expected/test/X/violations.json,
#      compared as JSON);
#   2. a second run is byte-identical (trajectories, violations);
#   3. `sdv convert` writes a .sdv that lints without a diagnostic and runs to byte-identical
#      trajectories.csv and violations.json.
# Trees are looked up in btrees/sdv (vehicles) and btrees/sp (pedestrians).
# Usage: geoscenario_test.sh SDV DATA_DIR
set -u
sdv=$1 data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
btrees=(--btree-path "$data/btrees/sdv" --btree-path "$data/btrees/sp")
failed=()
count=0
for scen in "$data"/scenarios/test/*.osm; do
    name=$(basename "$scen")
    count=$((count + 1))
    expected=$data/expected/test/$name/violations.json
    out=$tmp/$name
    fail=0
    if [ ! -f "$expected" ]; then
        echo "FAIL $name: no $expected"
        failed+=("$name")
        continue
    fi
    "$sdv" run "$scen" "${btrees[@]}" -o "$out/a" --gss-outputs > "$out.log" 2>&1
    # Equal as JSON: the same violations at the same tick keys (converted scenarios run at the
    # reference's rates, 40 / 5 Hz).
    same=$(python3 -c "
import json, sys
print(json.load(open(sys.argv[1])) == json.load(open(sys.argv[2])))" "$out/a/violations.json" "$expected" 2>&1)
    if [ "$same" != True ]; then
        echo "FAIL $name: violations differ from the reference's"
        echo "  sdv:       $(tr -d ' \n' < "$out/a/violations.json" 2>/dev/null)"
        echo "  reference: $(tr -d ' \n' < "$expected")"
        sed 's/^/  | /' "$out.log"
        fail=1
    fi
    "$sdv" run "$scen" "${btrees[@]}" -o "$out/b" --gss-outputs > /dev/null 2>&1
    for f in trajectories.csv violations.json; do
        cmp -s "$out/a/$f" "$out/b/$f" || { echo "FAIL $name: $f differs between two runs"; fail=1; }
    done
    mkdir -p "$out/conv"
    if ! "$sdv" convert "$scen" "${btrees[@]}" -o "$out/conv/x.sdv" > /dev/null 2> "$out/convert.err"; then
        echo "FAIL $name: sdv convert"
        sed 's/^/  | /' "$out/convert.err"
        failed+=("$name")
        continue
    fi
    "$sdv" lint "$out/conv/x.sdv" > "$out/lint.out" 2>&1
    if [ $? -ne 0 ] || [ -s "$out/lint.out" ]; then
        echo "FAIL $name: the converted file does not lint clean"
        sed 's/^/  | /' "$out/lint.out"
        fail=1
    fi
    "$sdv" run "$out/conv/x.sdv" -o "$out/c" --gss-outputs > /dev/null 2>&1
    for f in trajectories.csv violations.json; do
        cmp -s "$out/a/$f" "$out/c/$f" || { echo "FAIL $name: $f of the converted scenario differs from the original's"; fail=1; }
    done
    if [ $fail -eq 0 ]; then
        echo "ok   $name: $(tr -d ' \n' < "$expected") as the reference; deterministic; conversion lints clean and runs identically"
    else
        failed+=("$name")
    fi
done
if [ "$count" -eq 0 ]; then
    echo "FAIL: no scenario in $data/scenarios/test"
    exit 1
fi
if [ ${#failed[@]} -gt 0 ]; then
    echo "${#failed[@]} of $count scenarios fail: ${failed[*]}"
    exit 1
fi
echo "all $count scenarios of scenarios/test pass"
