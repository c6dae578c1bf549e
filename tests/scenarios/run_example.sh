#!/usr/bin/env bash
# `sdv run` of one example exits 0 (its expectations hold) and writes the outputs.
set -u
sdv=$1
ex=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$sdv" run "$ex" -o "$dir" --trace || exit 1
for f in trajectories.csv summary.json decisions.jsonl timing.json; do
    [ -s "$dir/$f" ] || { echo "missing $f"; exit 1; }
done
head -1 "$dir/trajectories.csv" | grep -qx 'time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver' || { echo "bad CSV header"; exit 1; }
python3 -c "import json,sys; s=json.load(open('$dir/summary.json')); assert s['passed'], s; [json.loads(l) for l in open('$dir/decisions.jsonl')]; print('outputs ok')"
