#!/usr/bin/env python3
"""Generates the table of docs/nhtsa.md from real runs: for every NHTSA scenario (the cut-in of
examples/cut_in.sdv is typology 18), the roads and trees it uses, the outcome of its run (the
collision, or the smallest outline clearance, same-lane bumper gap and time to collision between
the ego and the other vehicles) and its internal reuse level from `sdv reuse`. CI checks the
committed file is up to date:

    scripts/gen-nhtsa-doc.py build/dev/sdv            # rewrite the table in docs/nhtsa.md
    scripts/gen-nhtsa-doc.py build/dev/sdv --check    # exit 1 if it would change
"""
import json
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
sdv = str(pathlib.Path(sys.argv[1]).resolve())
files = [ROOT / "examples" / "cut_in.sdv"] + sorted((ROOT / "examples" / "nhtsa").glob("*.sdv"))


def typology(path):
    m = re.match(r"(\d+)_", path.name)
    return int(m.group(1)) if m else 18


rows = []
with tempfile.TemporaryDirectory() as tmp:
    for f in sorted(files, key=typology):
        text = f.read_text()
        out = pathlib.Path(tmp) / f.stem
        subprocess.run([sdv, "run", str(f), "-o", str(out)], capture_output=True, text=True)
        s = json.loads((out / "summary.json").read_text())
        road = re.search(r"^\s*road (\w+)", text, re.M).group(1)
        kind = "junction" if re.search(r"^junction " + road, text, re.M) else "road"
        control = re.search(r"control (\w+)", text)
        road_text = f"{kind} `{road}`" + (f" ({control.group(1)})" if control else "")
        trees = sorted(set(re.findall(r"tree (std\.\w+|\w+)\(", re.sub(r"^tree .*$", "", text, flags=re.M))))
        local = re.findall(r"^tree (\w+)\(", text, re.M)
        collisions = [e for e in s["events"] if e["kind"] == "collision" and "ego" in e["vehicles"]]
        if collisions:
            e = collisions[0]
            outcome = f"collision {' / '.join(e['vehicles'])} at {e['time']:.2f} s"
        else:
            pairs = [p for p in s["metrics"]["pairs"] if "ego" in p["vehicles"]]
            gap = min(pairs, key=lambda p: p["min_clearance"])
            ttc = min(p["min_ttc"] for p in pairs if p["min_ttc"] is not None) if any(p["min_ttc"] is not None for p in pairs) else None
            same_lane = [p["min_gap"] for p in pairs if p["min_gap"] is not None]
            outcome = (f"min clearance {gap['min_clearance']:.2f} m ({' / '.join(gap['vehicles'])})"
                       + (f", same-lane gap {min(same_lane):.2f} m" if same_lane else "")
                       + (f", min TTC {ttc:.2f} s" if ttc is not None else ""))
        held = sum(e["passed"] for e in s["expectations"])
        rows.append([typology(f), f.relative_to(ROOT).as_posix(), road_text,
                     ", ".join(f"`{t}`" for t in trees + [l for l in local if l not in trees]), outcome,
                     f"{held}/{len(s['expectations'])}", s["scenario"]])
    reuse = subprocess.run([sdv, "reuse"] + [str(f) for f in files], capture_output=True, text=True).stdout
irl = {}
overall = ""
for line in reuse.splitlines()[1:]:
    parts = line.split()
    if line.startswith("overall"):
        overall = f"{parts[-4]} over all nodes, {parts[-1]} over executed nodes"
    elif len(parts) >= 7:
        irl[parts[0]] = (parts[3], parts[6])

table = ["| # | scenario | road | trees | outcome (ego) | expectations | IRL all / executed |", "|---|---|---|---|---|---|---|"]
for t, f, road, trees, outcome, held, name in rows:
    a, e = irl.get(name, ("?", "?"))
    table.append(f"| {t} | `{f}` | {road} | {trees} | {outcome} | {held} | {a} / {e} |")
table.append("")
table.append(f"Overall (weighted by nodes): **{overall}**.")
body = "\n".join(table) + "\n"

doc = ROOT / "docs" / "nhtsa.md"
text = doc.read_text()
begin, end = "<!-- table: scripts/gen-nhtsa-doc.py -->\n", "<!-- end of table -->\n"
new = text[:text.index(begin) + len(begin)] + body + text[text.index(end):]
if "--check" in sys.argv:
    if new != text:
        print("docs/nhtsa.md is out of date: run scripts/gen-nhtsa-doc.py build/dev/sdv")
        sys.exit(1)
    print("docs/nhtsa.md matches the runs")
    sys.exit(0)
doc.write_text(new)
