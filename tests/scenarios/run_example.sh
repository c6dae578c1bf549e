#!/usr/bin/env bash
# `sdv run` of one example exits 0 (its expectations hold) and writes the outputs; a file with
# several scenarios runs each into its own directory.
set -u
sdv=$1
ex=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$sdv" run "$ex" -o "$dir" --trace || exit 1
runs=("$dir")
[ -e "$dir/trajectories.csv" ] || runs=("$dir"/*/)
for run in "${runs[@]}"; do
    run=${run%/}
    for f in trajectories.csv summary.json timing.json road.json; do
        [ -s "$run/$f" ] || { echo "missing $run/$f"; exit 1; }
    done
    # Decisions of every agent with a tree (a run of trajectory and path agents makes none).
    if awk -F, 'NR > 1 && $13 != "" { found = 1; exit } END { exit !found }' "$run/trajectories.csv"; then
        [ -s "$run/decisions.jsonl" ] || { echo "missing $run/decisions.jsonl"; exit 1; }
    fi
    head -1 "$run/trajectories.csv" | grep -qx 'time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver' || { echo "bad CSV header"; exit 1; }
    python3 -c "import json,sys; s=json.load(open('$run/summary.json')); assert s['passed'], s; import os; [json.loads(l) for l in (open('$run/decisions.jsonl') if os.path.exists('$run/decisions.jsonl') else [])]; r=json.load(open('$run/road.json')); assert r['lanes'] and all(len(l['centre']) >= 2 for l in r['lanes']); print('outputs ok')" || exit 1
    # The static figure: well-formed SVG naming every agent.
    "$sdv" plot "$run" -o "$run/fig.svg" || exit 1
    python3 - "$run" <<'PY' || exit 1
import csv, sys, xml.etree.ElementTree as ET
d = sys.argv[1]
svg = ET.parse(f"{d}/fig.svg").getroot()
texts = {t.text for t in svg.iter("{http://www.w3.org/2000/svg}text")}
vehicles = {r["vehicle"] for r in csv.DictReader(open(f"{d}/trajectories.csv"))}
missing = vehicles - texts
assert not missing, f"agents missing from the figure: {missing}"
print(f"figure ok: {len(vehicles)} agents")
PY
done
