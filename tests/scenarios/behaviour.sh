#!/usr/bin/env bash
# Sampled states and events of the examples, within tolerances (not whole traces).
set -u
sdv=$1
root=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for ex in following red_light cut_in obstacle; do
    "$sdv" run "$root/examples/$ex.sdv" -o "$dir/$ex" >/dev/null || { echo "FAIL: $ex does not pass"; exit 1; }
done
"$sdv" run "$root/tests/scenarios/data/trajectory.sdv" -o "$dir/trajectory" >/dev/null || { echo "FAIL: trajectory.sdv does not pass"; exit 1; }
python3 - "$dir" <<'PY'
import csv, json, sys
d = sys.argv[1]
def rows(name):
    return list(csv.DictReader(open(f"{d}/{name}/trajectories.csv")))
def at(rs, vehicle, t):
    return min((r for r in rs if r["vehicle"] == vehicle), key=lambda r: abs(float(r["time"]) - t))
fail = []
# Car following: from 30 s on, the follower keeps about its 2 s time gap behind the leader.
rs = rows("following")
for t in (30, 35, 40):
    f, l = at(rs, "follower", t), at(rs, "leader", t)
    gap = float(l["s"]) - float(f["s"]) - 4.5
    speed = float(f["speed"])
    headway = gap / speed
    print(f"following t={t}: gap {gap:.2f} m at {speed:.2f} m/s, headway {headway:.2f} s")
    if not (1.6 <= headway <= 2.6): fail.append(f"follower headway {headway:.2f} s at {t} s")
    if abs(speed - float(l["speed"])) > 0.5: fail.append(f"follower speed {speed:.2f} vs leader {l['speed']} at {t} s")
# Red light: the car stands still before the stop line while the light is red (10–20 s), then crosses.
rs = rows("red_light")
for t in (14, 18):
    c = at(rs, "car", t)
    print(f"red_light t={t}: {c['lane']} s={float(c['s']):.2f} speed={float(c['speed']):.2f}")
    if c["lane"] != "crossing.south.in" or abs(float(c["speed"])) > 0.05: fail.append(f"car not stopped at {t} s")
    if float(c["s"]) + 2.25 > 120.0 + 0.01: fail.append(f"car past the stop line at {t} s")
if at(rs, "car", 25)["lane"] != "crossing.north.out": fail.append("car did not cross after the light turned green")
# Cut-in: v2 ends in the ego's lane, ahead of it, and the ego reacts by following.
rs = rows("cut_in")
v2, ego = at(rs, "v2", 22), at(rs, "ego", 22)
print(f"cut_in t=22: v2 {v2['lane']} s={float(v2['s']):.1f}, ego {ego['lane']} s={float(ego['s']):.1f} {ego['maneuver']}")
if v2["lane"] != "highway.1" or float(v2["s"]) <= float(ego["s"]): fail.append("cut-in did not end in front of ego in lane 1")
if ego["maneuver"] != "follow": fail.append("ego does not follow v2 after the cut-in")
s = json.load(open(f"{d}/cut_in/summary.json"))
if any(e["kind"] == "collision" for e in s["events"]): fail.append("collision in cut_in")
# Obstacle: both SDVs pass the broken car in lane 2 and nobody collides.
rs = rows("obstacle")
for v in ("a", "b"):
    r = at(rs, v, 39)
    print(f"obstacle t=39: {v} {r['lane']} x={float(r['x']):.1f}")
    if float(r["x"]) < 250: fail.append(f"{v} did not pass the obstacle")
s = json.load(open(f"{d}/obstacle/summary.json"))
if any(e["kind"] == "collision" for e in s["events"]): fail.append("collision in obstacle")
# Trajectory vehicles interpolate their waypoints linearly; the SDV follows the stopping ego.
rs = rows("trajectory")
tr, e, car = at(rs, "truck", 10), at(rs, "e", 15), at(rs, "car", 19)
print(f"trajectory: truck x={float(tr['x']):.2f} at 10 s, ego x={float(e['x']):.2f} speed {float(e['speed']):.2f} at 15 s, car {car['maneuver']} speed {float(car['speed']):.2f} at 19 s")
if abs(float(tr["x"]) - 210) > 0.01: fail.append("truck not at its interpolated position")
if abs(float(e["x"]) - 200) > 0.01 or abs(float(e["speed"])) > 1e-6: fail.append("ego trajectory not holding at 200 m")
if car["maneuver"] != "follow" or float(car["speed"]) > 1.0: fail.append("car does not stop behind the stopped ego")
if fail:
    print("FAIL:", "; ".join(fail)); sys.exit(1)
print("all behaviour checks hold")
PY
