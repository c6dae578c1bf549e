#!/usr/bin/env bash
# Campaigns through the executable (docs/campaigns.md): a sweep's results are the same bytes for
# any --jobs, from source and from IR, when run as slices and merged, and after a sweep killed
# halfway (with a torn last row) is resumed, and when a row was damaged; --keep failed keeps exactly the failed variants;
# `sdv run --variant K` reproduces row K; the JUnit XML of run and sweep has the structure CI
# servers read; the search finds the known worst case of a scenario built for it, reproducibly,
# and writes it as a scenario that compiles and measures that value.
# Usage: campaign.sh SDV SOURCE_DIR
set -u
sdv=$1 src=$2
tmp=$(mktemp -d)
trap 'kill $pid 2>/dev/null; rm -rf "$tmp"' EXIT
pid=
fail=0
pass() { echo "PASS  $*"; }
bad() { echo "FAIL  $*"; fail=1; }
same() {  # same FILE_A FILE_B WHAT
    if cmp -s "$1" "$2"; then pass "$3"; else bad "$3"; diff "$1" "$2" | head -10; fi
}
table=$src/examples/sweeps/cut_in_table.sdv

# ---- jobs, source vs IR, slices
"$sdv" sweep "$table" -o "$tmp/j1" --jobs 1 > "$tmp/j1.log" 2>&1
rc=$?
[ $rc -eq 1 ] && pass "a sweep with failing variants exits 1" || bad "sweep exit $rc (expected 1)"
grep -q "35 variants" "$tmp/j1.log" && pass "35 variants reported" || { bad "report"; cat "$tmp/j1.log"; }
rows=$(($(wc -l < "$tmp/j1/results.csv") - 1))
[ "$rows" -eq 35 ] && pass "results.csv has one row per variant" || bad "results.csv has $rows rows"
"$sdv" sweep "$table" -o "$tmp/j2" --jobs 2 > /dev/null 2>&1
same "$tmp/j1/results.csv" "$tmp/j2/results.csv" "results.csv identical for --jobs 1 and 2"
same "$tmp/j1/summary.json" "$tmp/j2/summary.json" "summary.json identical for --jobs 1 and 2"
"$sdv" compile "$table" -o "$tmp/table.sdvir" > /dev/null
"$sdv" sweep "$tmp/table.sdvir" -o "$tmp/ir" --jobs 2 > /dev/null 2>&1
same "$tmp/j1/results.csv" "$tmp/ir/results.csv" "results.csv identical from source and from IR"
for i in 0 1 2; do "$sdv" sweep "$table" -o "$tmp/sl" --slice $i/3 > /dev/null 2>&1 || bad "slice $i/3"; done
[ ! -e "$tmp/sl/results.csv" ] && pass "a slice alone writes no results" || bad "a slice wrote results.csv"
"$sdv" sweep "$table" -o "$tmp/sl" --resume > "$tmp/sl.log" 2>&1
grep -q "35 of 35 variants were done" "$tmp/sl.log" && pass "the merge ran nothing again" || { bad "merge log"; cat "$tmp/sl.log"; }
same "$tmp/j1/results.csv" "$tmp/sl/results.csv" "three slices merged give the same results.csv"
same "$tmp/j1/summary.json" "$tmp/sl/summary.json" "three slices merged give the same summary.json"

# ---- --slurm-script-only: the array script; its tasks' command lines, run here, then merged.
# The scenario is named relative to the directory the script is written from, and the merge runs
# from another directory naming it another way: the rows are one campaign whatever the path.
(cd "$src/examples" && "$sdv" sweep sweeps/cut_in_table.sdv -o "$tmp/script" --slurm --slurm-script-only --array-tasks 3) > "$tmp/script.log" 2>&1 || bad "--slurm-script-only"
sb=$tmp/script/slurm/sweep.sbatch
if grep -q '^#SBATCH --array=0-2' "$sb" && grep -q -- '--slice' "$sb"; then pass "the script is a 3-task array running slices"; else bad "script"; cat "$sb"; fi
for i in 0 1 2; do SLURM_ARRAY_TASK_ID=$i bash "$sb" > /dev/null 2>&1 || bad "task $i of the script"; done
(cd "$src" && "$sdv" sweep ./examples/../examples/sweeps/cut_in_table.sdv -o "$tmp/script" --resume) > "$tmp/merge.log" 2>&1
grep -q "35 of 35 variants were done" "$tmp/merge.log" && pass "the merge from another directory ran nothing again" || { bad "merge log"; cat "$tmp/merge.log"; }
same "$tmp/j1/results.csv" "$tmp/script/results.csv" "the script's tasks, then --resume, give the local sweep's results.csv"

# ---- summary.json agrees with results.csv
python3 - "$tmp/j1" <<'EOF' && pass "summary.json counts agree with results.csv" || bad "summary.json counts"
import csv, json, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/results.csv")))
s = json.load(open(d + "/summary.json"))
assert s["format"] == "sdv-sweep/1" and s["variants"] == len(rows) == 35, s
assert s["passed"] == sum(r["passed"] == "1" for r in rows)
assert s["with_collision"] == sum(int(r["collisions"]) > 0 for r in rows) > 0, "the table has a collision"
assert s["expectation_failures"]["e2"] == sum(r["e2_passed"] == "0" for r in rows) > 0
assert [p["values"] for p in s["parameters"]] == [[2, 3, 4, 5, 6], [-8, -7, -6, -5, -4, -3, -2]], s["parameters"]
ttc = [float(r["min_ttc[s]"]) for r in rows if r["min_ttc[s]"]]
assert abs(s["worst"]["min_ttc"]["value"] - min(ttc)) < 1e-9
EOF

# ---- kill halfway, tear the last row, resume
big=$tmp/big.sdv
sed -e 's/v2.tree.accept_gap in 2 m .. 6 m count 5/v2.tree.accept_gap in 2 m .. 6 m/' \
    -e 's|v2.tree.dv in -8 m/s .. -2 m/s count 7|v2.tree.dv in -8 m/s .. -2 m/s|' \
    -e 's/sample grid/sample latin 300/' "$table" > "$big"
"$sdv" sweep "$big" -o "$tmp/full" --jobs 2 > /dev/null 2>&1
"$sdv" sweep "$big" -o "$tmp/killed" --jobs 1 > /dev/null 2>&1 &
pid=$!
rowsfile=$tmp/killed/rows/slice-0-of-1.csv
for _ in $(seq 1 3000); do
    [ -f "$rowsfile" ] && [ "$(wc -l < "$rowsfile")" -ge 40 ] && break
    sleep 0.01
done
kill -9 $pid 2>/dev/null
wait $pid 2>/dev/null
pid=
done_rows=$(wc -l < "$rowsfile")
if [ "$done_rows" -ge 40 ] && [ "$done_rows" -lt 300 ] && [ ! -e "$tmp/killed/results.csv" ]; then
    pass "killed after $done_rows of 300 variants"
else
    bad "the sweep was not killed halfway ($done_rows rows)"
fi
printf '299,3.1,-4' >> "$rowsfile"  # a row torn by the kill
"$sdv" sweep "$big" -o "$tmp/killed" --resume --jobs 2 > "$tmp/resume.log" 2>&1
grep -q "resumed: $done_rows of 300" "$tmp/resume.log" && pass "resume skipped the $done_rows complete rows" || { bad "resume log"; cat "$tmp/resume.log"; }
same "$tmp/full/results.csv" "$tmp/killed/results.csv" "results.csv after kill and resume identical to an uninterrupted sweep"
same "$tmp/full/summary.json" "$tmp/killed/summary.json" "summary.json after kill and resume identical"
"$sdv" sweep "$src/examples/cut_in.sdv" -o "$tmp/killed" --resume > "$tmp/other.log" 2>&1 && bad "resume of another scenario accepted" || pass "resume refuses the rows of another campaign"

# ---- a damaged row is named, run again on a resume, and the results are as if undamaged
cp -r "$tmp/j1" "$tmp/damaged"
python3 - "$tmp/damaged/rows/slice-0-of-1.csv" "$tmp/j1/results.csv" <<'EOF'
import sys
rows, header = sys.argv[1], open(sys.argv[2]).readline().rstrip("\n").split(",")
lines = open(rows).read().split("\n")
cells = lines[2].split(",")
cells[header.index("min_ttc[s]")] = "abc"
lines[2] = ",".join(cells)
open(rows, "w").write("\n".join(lines))
EOF
"$sdv" sweep "$table" -o "$tmp/damaged" --resume > "$tmp/damaged.log" 2>&1
grep -q "warning: 1 line of $tmp/damaged/rows is not a row as sdv writes it; .*($tmp/damaged/rows/slice-0-of-1.csv:3: 'min_ttc\[s\]' 'abc' is not a number)" "$tmp/damaged.log" &&
    grep -q "resumed: 34 of 35" "$tmp/damaged.log" && pass "a damaged row is named and its variant runs again" || { bad "damaged row"; cat "$tmp/damaged.log"; }
same "$tmp/j1/results.csv" "$tmp/damaged/results.csv" "results.csv after a damaged row and a resume identical"

# ---- keep failed, run --variant
"$sdv" sweep "$table" -o "$tmp/keep" --keep failed > /dev/null 2>&1
python3 - "$tmp/keep" <<'EOF' && pass "--keep failed keeps exactly the failed variants, each with view.html" || bad "--keep failed"
import csv, os, sys
d = sys.argv[1]
failed = {r["variant"] for r in csv.DictReader(open(d + "/results.csv")) if r["passed"] == "0"}
kept = set(os.listdir(d + "/runs"))
assert failed and kept == failed, (kept, failed)
for v in kept:
    for f in ("summary.json", "trajectories.csv", "view.html"):
        assert os.path.exists(f"{d}/runs/{v}/{f}"), (v, f)
EOF
k=$(python3 -c "
import csv; print(next(r['variant'] for r in csv.DictReader(open('$tmp/j1/results.csv')) if int(r['collisions']) > 0))")
"$sdv" run "$table" --variant "$k" -o "$tmp/v" --junit "$tmp/run.xml" > "$tmp/v.log" 2>&1
python3 - "$tmp/j1/results.csv" "$k" "$tmp/v/summary.json" <<'EOF' && pass "sdv run --variant $k reproduces row $k" || bad "run --variant"
import csv, json, sys
row = next(r for r in csv.DictReader(open(sys.argv[1])) if r["variant"] == sys.argv[2])
s = json.load(open(sys.argv[3]))
assert s["passed"] is False and row["passed"] == "0"
assert abs(s["expectations"][1]["value"] - float(row["e2[s]"])) < 1e-4 * max(1, abs(float(row["e2[s]"])))
assert any(e["kind"] == "collision" for e in s["events"])
EOF
# The sweep's runs share one road between variants (sim::RoadCache); a run alone builds its own.
same "$tmp/keep/runs/$k/trajectories.csv" "$tmp/v/trajectories.csv" "a kept variant's trajectories are those of sdv run --variant $k"
"$sdv" run "$table" --variant 35 -o "$tmp/v" > /dev/null 2>&1; [ $? -eq 2 ] && pass "--variant out of range is a usage error" || bad "--variant 35"

# ---- JUnit XML
"$sdv" sweep "$table" -o "$tmp/ju" --junit "$tmp/sweep.xml" > /dev/null 2>&1
python3 - "$tmp/run.xml" "$tmp/sweep.xml" "$tmp/j1/results.csv" <<'EOF' && pass "JUnit XML of run and sweep: structure, counts, measured values" || bad "JUnit XML"
import csv, sys, xml.etree.ElementTree as ET
def check(path):
    root = ET.parse(path).getroot()
    assert root.tag == "testsuites"
    total = failures = errors = 0
    for suite in root:
        assert suite.tag == "testsuite" and suite.get("name")
        cases = suite.findall("testcase")
        assert int(suite.get("tests")) == len(cases)
        assert int(suite.get("failures")) == sum(c.find("failure") is not None for c in cases)
        assert int(suite.get("errors")) == sum(c.find("error") is not None for c in cases)
        float(suite.get("time"))
        for c in cases:
            assert c.get("name") and c.get("classname")
            float(c.get("time"))
            f = c.find("failure")
            if f is not None:
                assert "measured" in f.get("message") and "expected" in f.get("message"), f.get("message")
        total += len(cases); failures += int(suite.get("failures")); errors += int(suite.get("errors"))
    assert int(root.get("tests")) == total and int(root.get("failures")) == failures and int(root.get("errors")) == errors
    return root
run = check(sys.argv[1])
assert len(run) == 1 and int(run.get("tests")) == 2 and int(run.get("failures")) == 2, ET.tostring(run)[:300]
sweep = check(sys.argv[2])
rows = list(csv.DictReader(open(sys.argv[3])))
assert len(sweep) == len(rows) == 35
assert int(sweep.get("failures")) == sum((r["e1_passed"] == "0") + (r["e2_passed"] == "0") for r in rows)
EOF

# ---- search: the known worst case, reproducibly, written as a scenario
known=$src/tests/cli/data/search_known_worst.sdv
"$sdv" search "$known" --minimize 'min_clearance(a, b)' --budget 60 --seed 7 -o "$tmp/s1" > "$tmp/s1.log" 2>&1 || { bad "search"; cat "$tmp/s1.log"; }
"$sdv" search "$known" --minimize 'min_clearance(a, b)' --budget 60 --seed 7 -o "$tmp/s2" > /dev/null 2>&1
same "$tmp/s1/search.csv" "$tmp/s2/search.csv" "the search is reproducible for a seed"
python3 - "$tmp/s1/search.csv" <<'EOF' && pass "the search finds the known worst case (1.6 m with b alongside a and 2 m wide)" || bad "search result"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["min_clearance(a, b)[m]"]]
assert len(rows) <= 60
best = min(rows, key=lambda r: float(r["min_clearance(a, b)[m]"]))
assert abs(float(best["min_clearance(a, b)[m]"]) - 1.6) < 0.005, best
assert 45.5 <= float(best["b.start[m]"]) <= 54.5 and float(best["b.width[m]"]) > 1.99, best
EOF
"$sdv" run "$tmp/s1/worst.sdv" -o "$tmp/w" > /dev/null 2>&1
python3 -c "
import json; s = json.load(open('$tmp/w/summary.json'))
v = s['expectations'][0]['value']; assert abs(v - 1.6) < 0.005, v" && pass "worst.sdv compiles, runs and measures the worst case" || bad "worst.sdv"
grep -q "vary" "$tmp/s1/worst.sdv" && bad "worst.sdv still varies" || pass "worst.sdv has no vary block"
"$sdv" search "$known" --minimize 'min_clearance(a, c)' -o "$tmp/s3" > /dev/null 2>&1; [ $? -eq 2 ] && pass "an unknown vehicle in the metric is a usage error" || bad "metric check"
"$sdv" sweep "$src/examples/cut_in.sdv" -o "$tmp/none" > /dev/null 2>&1; [ $? -eq 1 ] && pass "a scenario without vary cannot be swept" || bad "sweep without vary"

exit $fail
