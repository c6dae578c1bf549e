#!/usr/bin/env bash
# GeoScenario's external vehicles (btype EV) become external vehicles of the converted scenario,
# which a co-simulation client then drives: the reference's straightdrive_2vehicles with v2 made
# an EV converts to `vehicle v2: external`, and the Python package (C API) drives v2 along its
# lane while v1 (an SDV) drives by its tree to the end of the run.
# Usage: gss_external.sh SDV LIBSDV DATA_DIR
set -eu
sdv=$1 lib=$2 data=$3
# A sanitizer build's test environment preloads the sanitizer runtimes for a Python host of
# libsdv.so (sdv_foreign_host_test); sdv links its own, so only that host may get them.
host=(env ${LD_PRELOAD:+"LD_PRELOAD=$LD_PRELOAD"} ${ASAN_OPTIONS:+"ASAN_OPTIONS=$ASAN_OPTIONS"})
unset LD_PRELOAD ASAN_OPTIONS
root=$(cd "$(dirname "$0")/../../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The first btype of the file is v2's.
sed "0,/<tag k='btype' v='SDV' \/>/s//<tag k='btype' v='EV' \/>/" \
    "$data/scenarios/straightdrive_2vehicles.gs.osm" > "$tmp/ext.gs.osm"
"$sdv" convert "$tmp/ext.gs.osm" --btree-path "$data/btrees/sdv" --map-dir "$data" -o "$tmp/ext.sdv" > /dev/null
grep -q '^    vehicle v2: external {$' "$tmp/ext.sdv" || { echo "FAIL: v2 is not external:"; cat "$tmp/ext.sdv"; exit 1; }
"$sdv" lint "$tmp/ext.sdv"
SDV_LIBRARY=$lib PYTHONPATH=$root/python "${host[@]}" python3 - "$tmp/ext.sdv" "$tmp/out" <<'PY'
import math, sys
import sdv
with sdv.Simulation(sys.argv[1], output_dir=sys.argv[2]) as sim:
    v2 = sim.claim("v2")
    start = {s.id: s for s in sim.states()}
    last_d = start[v2].d
    while sim.run_state == sdv.RUNNING:
        me = sim.states()[v2 - 1]
        yaw = me.yaw + (-0.4 * me.d - 1.2 * (me.d - last_d) * 30) / 30
        last_d = me.d
        speed = min(me.speed + 0.1, 8.0)
        sim.set_state(v2, x=me.x + speed * math.cos(yaw) / 30, y=me.y + speed * math.sin(yaw) / 30, yaw=yaw, speed=speed)
        sim.step()
        assert abs(me.d) < 0.5, f"v2 left its lane: d = {me.d:.2f} at tick {sim.tick}"
    end = {s.id: s for s in sim.states()}
    moved = {i: math.hypot(end[i].x - start[i].x, end[i].y - start[i].y) for i in end}
    assert all(m > 50 for m in moved.values()), moved
    sim.finish()
    print(f"v2 (external) and v1 (sdv) drove {moved[v2]:.0f} m and {moved[3 - v2]:.0f} m; run ended at tick {sim.tick}")
PY
grep -q '"ending": "finished"' "$tmp/out/summary.json"
