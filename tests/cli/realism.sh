#!/usr/bin/env bash
# Realism through the executable (docs/realism.md): `sdv replay` on every committed recording
# replaces every recorded vehicle, with realism.csv/json the same bytes for --jobs 1 and 2 and
# across runs; each replay's SDV is the replaced vehicle and everyone else follows the
# recording; `sdv convert` of a recording compiles; `sdv calibrate` recovers the speed of a
# synthetic recording made by sdv itself with known parameters, reproducibly; bad input gives
# located errors.
# Usage: realism.sh SDV SOURCE_DIR [quick]
# `quick` (the sanitizer build): the replays of the three smaller recordings only.
set -u
sdv=$1 src=$2 mode=${3:-full}
rec=$src/../shared/data/recorded/commonroad
data=$src/tests/cli/data/realism
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
pass() { echo "PASS  $*"; }
bad() { echo "FAIL  $*"; fail=1; }
same() {  # same FILE_A FILE_B WHAT
    if cmp -s "$1" "$2"; then pass "$3"; else bad "$3"; diff "$1" "$2" | head -10; fi
}

# ---- replay every vehicle of every recording
for f in "$rec"/*.xml; do
    name=$(basename "$f" .xml)
    case $mode:$name in quick:USA_Lanker-1_1_T-1 | quick:USA_US101-4_1_T-1) continue ;; esac
    "$sdv" replay "$f" -o "$tmp/$name.1" --jobs 1 > "$tmp/$name.log" 2>&1 || { bad "$name: replay exit $?"; cat "$tmp/$name.log"; continue; }
    "$sdv" replay "$f" -o "$tmp/$name.2" --jobs 2 > /dev/null 2>&1
    same "$tmp/$name.1/realism.csv" "$tmp/$name.2/realism.csv" "$name: realism.csv identical for --jobs 1 and 2"
    same "$tmp/$name.1/realism.json" "$tmp/$name.2/realism.json" "$name: realism.json identical for --jobs 1 and 2"
    # One row per recorded vehicle, each compared, STED within [0, max distance].
    python3 - "$f" "$tmp/$name.1/realism.csv" <<'PY' && pass "$name: every vehicle replaced and compared" || bad "$name: rows"
import csv, sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
ids = {o.get("id") for o in root if o.tag == "dynamicObstacle" or (o.tag == "obstacle" and o.findtext("role") == "dynamic")}
ids = {i for i in ids if len([o for o in root if o.get("id") == i][0].findall("trajectory/state")) > 0}
rows = list(csv.DictReader(open(sys.argv[2])))
assert {r["vehicle"] for r in rows} == ids, (len(rows), len(ids))
for r in rows:
    assert r["sted_m"] != "", r
    assert 0 <= float(r["sted_m"]) <= float(r["max_distance_m"]) + 1e-9, r
    assert not r["outcome"].startswith("error"), r
PY
done
# A replay run: the replaced vehicle is the only SDV; its trajectories are the same bytes again.
first=$(sed -n 2p "$tmp/USA_Peach-4_8_T-1.1/realism.csv" | cut -d, -f1)
run="$tmp/USA_Peach-4_8_T-1.1/runs/v$first"
kinds=$(cut -d, -f3,4 "$run/trajectories.csv" | sort -u | awk -F, '$2=="sdv"{print $1}')
[ "$kinds" = "v$first" ] && pass "the replaced vehicle v$first is the run's only SDV" || bad "SDVs in the replay: $kinds"
[ -s "$run/recorded.csv" ] && pass "the run keeps the recorded path (recorded.csv)" || bad "no recorded.csv"
"$sdv" run "$run/scenario.sdv" -o "$tmp/again" > /dev/null 2>&1
same "$run/trajectories.csv" "$tmp/again/trajectories.csv" "the written scenario.sdv runs to the same trajectories"
"$sdv" view "$run" -o "$tmp/view.html" > /dev/null 2>&1 && grep -q '"recorded"' "$tmp/view.html" \
    && pass "sdv view shows the recorded path" || bad "sdv view without the recorded path"

# ---- convert
"$sdv" convert "$rec/USA_US101-3_3_T-1.xml" -o "$tmp/us101.sdv" > /dev/null 2>&1 && pass "convert: a recording as a scenario" || bad "convert"
"$sdv" run "$tmp/us101.sdv" -o "$tmp/us101" > /dev/null 2>&1
[ $? -le 1 ] && [ -s "$tmp/us101/trajectories.csv" ] && pass "the converted recording runs" || bad "converted recording run"

# ---- calibration on a synthetic recording with known parameters (speed 12 m/s, time gap 1.2 s)
for s in follow solo other; do "$sdv" run "$data/$s.sdv" -o "$tmp/syn-$s" > /dev/null 2>&1 || bad "synthetic run $s"; done
python3 "$data/to_interaction.py" "$tmp/tracks.csv" "$tmp/syn-follow" "$tmp/syn-solo" "$tmp/syn-other"
map=$rec/USA_US101-4_1_T-1.xml
cal() { "$sdv" calibrate "$tmp/tracks.csv" --map "$map" --sdv follower,solo,other --params speed,time_gap --budget 40 --split 1 "$@"; }
cal -o "$tmp/cal1" --jobs 1 > "$tmp/cal.log" 2>&1 || { bad "calibrate exit"; cat "$tmp/cal.log"; }
cal -o "$tmp/cal2" --jobs 2 > /dev/null 2>&1
same "$tmp/cal1/calibration.json" "$tmp/cal2/calibration.json" "calibration.json identical for --jobs 1 and 2 (seeded)"
same "$tmp/cal1/calibration.csv" "$tmp/cal2/calibration.csv" "every evaluation identical for --jobs 1 and 2"
python3 - "$tmp/cal1/calibration.json" <<'PY' && pass "the fit recovers speed (12 m/s within 0.2) and time gap (1.2 s within 0.1), STED below 0.3 m" || { bad "fit"; cat "$tmp/cal.log"; }
import json, sys
j = json.load(open(sys.argv[1]))
p = {x["name"]: x["fitted"] for x in j["params"]}
assert abs(p["speed"] - 12) <= 0.2 and abs(p["time_gap"] - 1.2) <= 0.1, p
assert j["training"]["sted_after_m"] < 0.3 and j["training"]["sted_after_m"] < j["training"]["sted_before_m"] / 10, j["training"]
PY
# With the true parameters, each replay is its original again (the leader replayed from 10 Hz).
"$sdv" replay "$tmp/tracks.csv" --map "$map" --sdv follower,solo,other --tree "std.drive(speed = 12 m/s, time_gap = 1.2 s)" \
    -o "$tmp/truth" > /dev/null 2>&1
python3 - "$tmp/truth/realism.csv" <<'PY' && pass "replays with the true parameters are within 1 cm of their recordings" || { bad "truth"; cat "$tmp/truth/realism.csv"; }
import csv, sys
assert all(float(r["max_distance_m"]) < 0.01 for r in csv.DictReader(open(sys.argv[1])))
PY
# A track that starts later (INTERACTION tracks do) enters the replay at its first recorded time.
awk -F, 'NR == 1 || $1 != "other" || $3 >= 2000' "$tmp/tracks.csv" > "$tmp/late.csv"
"$sdv" convert "$tmp/late.csv" --map "$map" --sdv solo -o "$tmp/late.sdv" > /dev/null 2>&1 || bad "convert with a late track"
awk '/vother: trajectory/ {f = 1} f && / s: at / {print $1; exit}' "$tmp/late.sdv" | grep -qx "2" \
    && pass "a late track is replayed from its first recorded time (2 s)" || { bad "late track"; grep -A4 vother "$tmp/late.sdv"; }
"$sdv" run "$tmp/late.sdv" -o "$tmp/late" > /dev/null 2>&1
first=$(awk -F, '$3 == "vother" {print $1; exit}' "$tmp/late/trajectories.csv")
[ "$first" = "2.0000" ] && pass "it enters the run at 2 s" || bad "it enters at '$first'"
"$sdv" lint "$tmp/cal1/calibrated.sdv" > /dev/null 2>&1 && pass "calibrated.sdv is a tree that compiles" || bad "calibrated.sdv"
"$sdv" calibrate "$tmp/tracks.csv" --map "$map" --sdv follower,solo,other --params speed --split 0.67 --budget 10 -o "$tmp/cal3" > "$tmp/cal3.log" 2>&1
grep -q "held out (1 vehicles)" "$tmp/cal3.log" && pass "a split reports held-out STED" || { bad "held-out"; cat "$tmp/cal3.log"; }

# ---- errors
"$sdv" replay "$rec/USA_US101-3_3_T-1.xml" --sdv 99999 -o "$tmp/e1" > "$tmp/e1.log" 2>&1
[ $? -eq 2 ] && grep -q "no agent '99999'" "$tmp/e1.log" && pass "an unknown --sdv id is a usage error naming it" || bad "unknown id"
"$sdv" calibrate "$tmp/tracks.csv" --map "$map" --params nosuch -o "$tmp/e2" > "$tmp/e2.log" 2>&1
[ $? -eq 2 ] && grep -q "its parameters: speed, time_gap, look_ahead" "$tmp/e2.log" && pass "an unknown parameter lists the tree's" || { bad "unknown param"; cat "$tmp/e2.log"; }
printf 'track_id,frame_id,timestamp_ms,agent_type,x,y,vx,vy\n1,1,0,car,0,0,0,0\n1,2,nan,car,0,0,0,0\n' > "$tmp/bad.csv"
"$sdv" replay "$tmp/bad.csv" --map "$map" -o "$tmp/e3" > "$tmp/e3.log" 2>&1
[ $? -eq 1 ] && grep -q "bad.csv:3:" "$tmp/e3.log" && pass "a malformed track file: error at its line" || { bad "bad csv"; cat "$tmp/e3.log"; }
"$sdv" replay "$tmp/bad.csv" -o "$tmp/e4" > "$tmp/e4.log" 2>&1
grep -q "needs its Lanelet2 map (--map)" "$tmp/e4.log" && pass "INTERACTION tracks without --map: says so" || { bad "no map"; cat "$tmp/e4.log"; }

[ $fail -eq 0 ] && echo "all realism checks passed" || echo "FAIL"
exit $fail
