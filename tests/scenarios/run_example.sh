#!/usr/bin/env bash
# `sdv run` of one example exits 0 (its expectations hold) and writes the outputs.
set -u
sdv=$1
ex=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$sdv" run "$ex" -o "$dir" --trace || exit 1
for f in trajectories.csv summary.json decisions.jsonl timing.json road.json; do
    [ -s "$dir/$f" ] || { echo "missing $f"; exit 1; }
done
head -1 "$dir/trajectories.csv" | grep -qx 'time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver' || { echo "bad CSV header"; exit 1; }
python3 -c "import json,sys; s=json.load(open('$dir/summary.json')); assert s['passed'], s; [json.loads(l) for l in open('$dir/decisions.jsonl')]; r=json.load(open('$dir/road.json')); assert r['lanes'] and all(len(l['centre']) >= 2 for l in r['lanes']); print('outputs ok')"
# The static figure: well-formed SVG naming every vehicle.
"$sdv" plot "$dir" -o "$dir/fig.svg" || exit 1
python3 - "$dir" <<'PY'
import csv, sys, xml.etree.ElementTree as ET
d = sys.argv[1]
svg = ET.parse(f"{d}/fig.svg").getroot()
texts = {t.text for t in svg.iter("{http://www.w3.org/2000/svg}text")}
vehicles = {r["vehicle"] for r in csv.DictReader(open(f"{d}/trajectories.csv"))}
missing = vehicles - texts
assert not missing, f"vehicles missing from the figure: {missing}"
print(f"figure ok: {len(vehicles)} vehicles")
PY
