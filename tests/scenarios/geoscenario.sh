#!/usr/bin/env bash
# One GeoScenario scenario of shared/data/geoscenario, end to end (SPEC §8):
#   1. `sdv run X.gs.osm --gss-outputs` gives the reference's outcome (expected/X/violations.json,
#      compared as JSON);
#   2. a second run is byte-identical (trajectories, violations);
#   3. `sdv convert` writes a .sdv that lints without a diagnostic and runs to byte-identical
#      trajectories.csv and violations.json.
# Usage: geoscenario.sh SDV DATA_DIR NAME
set -u
sdv=$1 data=$2 name=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scen=$data/scenarios/$name.gs.osm
expected=$data/expected/$name.gs.osm/violations.json
fail=0
"$sdv" run "$scen" --btree-path "$data/btrees/sdv" -o "$tmp/a" --gss-outputs > "$tmp/a.log" 2>&1
same=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1])) == json.load(open(sys.argv[2])))" "$tmp/a/violations.json" "$expected")
if [ "$same" != True ]; then
    echo "FAIL: violations differ from the reference's"
    echo "  sdv:       $(tr -d ' \n' < "$tmp/a/violations.json")"
    echo "  reference: $(tr -d ' \n' < "$expected")"
    cat "$tmp/a.log"
    fail=1
else
    echo "outcome matches the reference: $(tr -d ' \n' < "$expected")"
fi
if [ "$name" = 4waystop ]; then
    # All four drivers take their turn: each crosses the junction (approach lanelet, a lanelet
    # inside the junction, exit lanelet) and ends far from where it started.
    python3 - "$tmp/a/trajectories.csv" <<'PY' || fail=1
import collections, csv, math, sys
rows = collections.defaultdict(list)
for r in csv.DictReader(open(sys.argv[1])):
    rows[r["vehicle"]].append(r)
ok = True
for v, rs in sorted(rows.items()):
    lanes = [l for i, l in enumerate(r["lane"] for r in rs) if l and (i == 0 or rs[i - 1]["lane"] != l)]
    moved = math.hypot(float(rs[-1]["x"]) - float(rs[0]["x"]), float(rs[-1]["y"]) - float(rs[0]["y"]))
    crossed = len(set(lanes)) >= 3 and moved > 40
    ok = ok and crossed
    print(("ok" if crossed else "FAIL") + f": {v} crosses: lanes {' -> '.join(lanes)}, {moved:.0f} m from its start")
sys.exit(0 if ok and len(rows) == 4 else 1)
PY
fi
if [ "$name" = trafficlight_red ]; then
    # The light of this scenario is red from 2.5 s to 12.5 s: the SDV waits at it, then goes.
    python3 - "$tmp/a/trajectories.csv" <<'PY' || fail=1
import csv, sys
rows = {round(float(r["time"]), 2): r for r in csv.DictReader(open(sys.argv[1])) if r["vehicle"] == "v1"}
still = all(abs(float(rows[t]["speed"])) < 0.05 for t in (10.0, 12.0))
going = float(rows[16.0]["speed"]) > 3
print(("ok" if still and going else "FAIL") + f": red light respected: speed {rows[10.0]['speed']} at 10 s, {rows[12.0]['speed']} at 12 s, {rows[16.0]['speed']} at 16 s")
sys.exit(0 if still and going else 1)
PY
fi
for f in trajectory_v1.csv; do
    [ -f "$tmp/a/$f" ] || { echo "FAIL: no $f"; fail=1; }
    head -1 "$tmp/a/$f" | grep -q '^id,type,sim_state,tick_count,sim_time,delta_time,x,x_vel,x_acc,y,y_vel,y_acc,s,s_vel,s_acc,d,d_vel,d_acc,angle$' \
        || { echo "FAIL: $f does not have the reference's 19 columns"; fail=1; }
done
"$sdv" run "$scen" --btree-path "$data/btrees/sdv" -o "$tmp/b" --gss-outputs > /dev/null 2>&1
for f in trajectories.csv violations.json; do
    cmp -s "$tmp/a/$f" "$tmp/b/$f" || { echo "FAIL: $f differs between two runs"; fail=1; }
done
# Conversion.
mkdir -p "$tmp/conv"
if ! "$sdv" convert "$scen" --btree-path "$data/btrees/sdv" -o "$tmp/conv/$name.sdv" > /dev/null 2> "$tmp/convert.err"; then
    echo "FAIL: sdv convert"; cat "$tmp/convert.err"; exit 1
fi
"$sdv" lint "$tmp/conv/$name.sdv" > "$tmp/lint.out" 2>&1
if [ $? -ne 0 ] || [ -s "$tmp/lint.out" ]; then
    echo "FAIL: the converted file does not lint clean"; cat "$tmp/lint.out"; fail=1
fi
"$sdv" run "$tmp/conv/$name.sdv" -o "$tmp/c" --gss-outputs > /dev/null 2>&1
for f in trajectories.csv violations.json; do
    cmp -s "$tmp/a/$f" "$tmp/c/$f" || { echo "FAIL: $f of the converted scenario differs from the original's"; fail=1; }
done
[ $fail -eq 0 ] && echo "ok: $name (deterministic; conversion lints clean and runs identically)"
exit $fail
