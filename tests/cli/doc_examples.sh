#!/usr/bin/env bash
# Every ```sdv block in the docs is a complete file that lints clean (-Werror): the examples
# in the documentation cannot drift from the compiler.
set -u
sdv=$1
root=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$root/docs" "$dir" <<'PY'
import pathlib, re, sys
docs, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
n = 0
for md in sorted(docs.glob("*.md")):
    for i, block in enumerate(re.findall(r"^```sdv\n(.*?)^```", md.read_text(), re.S | re.M)):
        (out / f"{md.stem}_{i + 1}.sdv").write_text(block)
        n += 1
print(f"{n} examples extracted")
PY
fail=0
for f in "$dir"/*.sdv; do
    [ -e "$f" ] || continue
    out=$("$sdv" lint -Werror "$f" 2>&1)
    if [ $? -ne 0 ] || [ -n "$out" ]; then
        echo "FAIL $(basename "$f"):"
        echo "$out"
        fail=1
        continue
    fi
    # Examples with a scenario must also run with their expectations holding; one with an
    # external vehicle, with the reference co-simulation client driving it.
    if grep -q ': external' "$f"; then
        port=$dir/port_$(basename "$f" .sdv)
        "$sdv" run "$f" --cosim tcp://127.0.0.1:0 --cosim-port-file "$port" --cosim-encoding json \
            --cosim-step-timeout 60 -o "$dir/out_$(basename "$f" .sdv)" > "$dir/cosim.log" 2>&1 &
        server=$!
        client=$(python3 "$root/examples/cosim/ads_client.py" --port-file "$port" 2>&1)
        ccode=$?
        wait "$server"
        if [ $? -ne 0 ] || [ $ccode -ne 0 ]; then
            echo "FAIL $(basename "$f") does not run with the reference client:"
            echo "$client"
            cat "$dir/cosim.log"
            fail=1
            continue
        fi
        echo "ok   $(basename "$f") (lints and runs, co-simulated)"
    elif grep -q '^scenario ' "$f"; then
        if ! out=$("$sdv" run "$f" -o "$dir/out_$(basename "$f" .sdv)" 2>&1); then
            echo "FAIL $(basename "$f") does not run:"
            echo "$out"
            fail=1
            continue
        fi
        echo "ok   $(basename "$f") (lints and runs)"
    else
        echo "ok   $(basename "$f")"
    fi
done
# The outputs quoted in the tutorial are the tool's real outputs.
python3 - "$sdv" "$root/docs/tutorial.md" "$dir" <<'PY' || fail=1
import os, re, subprocess, sys
sdv, md, d = os.path.abspath(sys.argv[1]), sys.argv[2], sys.argv[3]
text = open(md).read()
blocks = re.findall(r"^```sdv\n(.*?)^```", text, re.S | re.M)
quoted = re.findall(r"^```text\n(.*?)^```", text, re.S | re.M)
open(f"{d}/first.sdv", "w").write(blocks[0].replace("tree std.drive(speed = 50 km/h)", "tree std.drive(speed = 50 km)"))
lint = subprocess.run([sdv, "lint", "first.sdv"], cwd=d, capture_output=True, text=True).stderr
want = next(q for q in quoted if q.startswith("first.sdv"))
open(f"{d}/cut_in.sdv", "w").write(blocks[1])
open(f"{d}/cut_in_wide.sdv", "w").write(blocks[2])
diff = subprocess.run([sdv, "diff", "cut_in.sdv", "cut_in_wide.sdv"], cwd=d, capture_output=True, text=True).stdout
want_diff = next(q for q in quoted if q.startswith("vehicle v2"))
run = subprocess.run([sdv, "run", "cut_in.sdv", "-o", "out/cut_in", "--trace", "--view"], cwd=d, capture_output=True, text=True).stdout
got_view = run.splitlines()[-1] + "\n" if run else ""
want_view = next(q for q in quoted if q.startswith("report in"))
report = os.path.join(d, "out/cut_in/report.html")
ok = True
if not os.path.exists(report) or "sdv-view/1" not in open(report).read():
    print("FAIL tutorial: no report with its data at out/cut_in/report.html")
    ok = False
view = subprocess.run([sdv, "view", "out/cut_in", "-o", "report.html"], cwd=d, capture_output=True, text=True)
if view.returncode != 0 or open(os.path.join(d, "report.html")).read() != open(report).read():
    print("FAIL tutorial: sdv view does not write the same report as sdv run --view")
    ok = False
for name, got, exp in (("error example", lint, want), ("diff example", diff, want_diff), ("view example", got_view, want_view)):
    if got != exp:
        print(f"FAIL tutorial {name} differs:\n--- documented\n{exp}--- actual\n{got}")
        ok = False
    else:
        print(f"ok   tutorial {name} matches the tool")
sys.exit(0 if ok else 1)
PY
exit $fail
