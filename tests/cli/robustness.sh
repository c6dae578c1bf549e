#!/usr/bin/env bash
# Bad input never crashes or hangs (SPEC §10): each input below must give exit code 1 and a
# located error (`file:line:col: error[E....]`). The timeout only tells a hang from slow work:
# it is far above any build's time (the 10 MB file takes over 60 s under ASan+UBSan on a busy
# 2-core machine); the front end's speed is measured in bench/, not here.
#   robustness.sh SDV
set -u
sdv=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0

check() {  # check NAME FILE [EXPECTED_CODE]
    local name=$1 file=$2
    local err
    err=$(timeout 900 "$sdv" lint "$file" 2>&1 >/dev/null)
    local code=$?
    if [ "$code" != 1 ]; then
        echo "FAIL $name: exit code $code (expected 1)"
        fail=1
    elif ! grep -qE "^$file:[0-9]+:[0-9]+: error\[E[0-9]{4}\]" <<<"$err"; then
        echo "FAIL $name: no located error in:"
        head -5 <<<"$err"
        fail=1
    else
        echo "ok   $name: $(grep -m1 -oE 'error\[E[0-9]{4}\].*' <<<"$err" | cut -c1-90)"
    fi
}

: > "$dir/empty.sdv"
printf 'scenario s {\n    road r\n}\n' > "$dir/no_road_decl.sdv"
head -c 4096 /dev/urandom > "$dir/garbage.sdv"
printf '\x00\x01\x02tree\x00' > "$dir/nul.sdv"
python3 - "$dir" <<'PY'
import sys
d = sys.argv[1]
# 10 MB of valid trees with one error at the very end.
with open(f"{d}/huge.sdv", "w") as f:
    t = "tree t{}() {{\n    maneuver keep_velocity(speed = 14 m/s)\n}}\n"
    i = 0
    while f.tell() < 10 * 1024 * 1024:
        f.write(t.format(i)); i += 1
    f.write("tree bad() {\n    maneuver keep_velocity(speed = 5 m)\n}\n")
with open(f"{d}/deep.sdv", "w") as f:
    f.write("tree t() {\n" + "sequence {" * 10000 + "maneuver keep_velocity()" + "}" * 10000 + "\n}\n")
with open(f"{d}/deep_not.sdv", "w") as f:
    f.write("tree t() {\n" + "not " * 10000 + "condition sim_time(after = 1 s)\n}\n")
with open(f"{d}/deep_parens.sdv", "w") as f:
    f.write("scenario s {\n    expect " + "(" * 10000 + "timeout()" + ")" * 10000 + "\n}\n")
with open(f"{d}/nan.sdv", "w") as f:
    f.write("tree t() {\n    maneuver keep_velocity(speed = NaN m/s)\n}\n")
with open(f"{d}/nan_name.sdv", "w") as f:
    f.write("tree t() {\n    maneuver keep_velocity(speed = nan)\n}\n")
with open(f"{d}/huge_number.sdv", "w") as f:
    f.write("tree t() {\n    maneuver keep_velocity(speed = 1e308 m/s)\n}\n")
with open(f"{d}/overflow.sdv", "w") as f:
    f.write("tree t() {\n    maneuver keep_velocity(speed = 1e308 km/h)\n}\n")
with open(f"{d}/unknown_unit.sdv", "w") as f:
    f.write("tree t() {\n    maneuver keep_velocity(speed = 14 furlong)\n}\n")
with open(f"{d}/unterminated.sdv", "w") as f:
    f.write('import "std/drive.sdv\ntree t() {\n    maneuver keep_velocity()\n}\n')
with open(f"{d}/long_line.sdv", "w") as f:
    f.write("tree t() { maneuver keep_velocity(" + "speed = 1 m/s, " * 20000 + ") }\n")
with open(f"{d}/many_errors.sdv", "w") as f:
    f.write("tree t() {\n    fallback {\n" + "        maneuver keep_velocity(speed = 5 m)\n" * 5000 + "    }\n}\n")
# Found by the in-process fuzzers (issue 22): an expectation of 7,900 `and`, 15,000 nested
# brackets in a .btree value, a .btree whose first line is indented then dedented.
with open(f"{d}/and_chain.sdv", "w") as f:
    f.write("scenario s {\n    expect " + " and ".join(["no_collision()"] * 7900) + "\n}\n")
with open(f"{d}/deep_brackets.btree", "w") as f:
    f.write("behaviortree t:\n    maneuver m(MVelKeepConfig(vel=" + "(" * 15000 + "1" + ")" * 15000 + "))\n")
with open(f"{d}/indented_first.btree", "w") as f:
    f.write(" a\nb")
with open(f"{d}/huge_samples.sdv", "w") as f:
    f.write("tree t() {\n    maneuver keep_velocity(speed = 14 m/s +- 10% samples 99999999999999999999999)\n}\n")
PY
for f in empty no_road_decl garbage nul huge deep deep_not deep_parens nan nan_name huge_number \
         overflow unknown_unit unterminated long_line many_errors huge_samples and_chain; do
    check "$f" "$dir/$f.sdv"
done
for f in deep_brackets indented_first; do
    check "$f" "$dir/$f.btree"
done

# Maps and IR that `sdv run` reads: a located error, never a crash or a hang (issue 22).
run_check() {  # run_check NAME FILE PATTERN
    local out code
    out=$(timeout 900 "$sdv" run "$2" -o "$dir/out" 2>&1)
    code=$?
    if [ "$code" = 1 ] && grep -qE "$3" <<<"$out"; then
        echo "ok   $1: $(grep -m1 -E "$3" <<<"$out" | cut -c1-110)"
    else
        echo "FAIL $1: exit code $code, expected 1 and /$3/:"
        tail -5 <<<"$out"
        fail=1
    fi
}
map() {  # map NAME X: one lanelet whose far end is at local_x = X
    cat > "$dir/$1.osm" <<XML
<?xml version="1.0"?>
<osm version="0.6">
  <node id="1" lat="0" lon="0"><tag k="local_x" v="0"/><tag k="local_y" v="0"/></node>
  <node id="2" lat="0" lon="0"><tag k="local_x" v="$2"/><tag k="local_y" v="0"/></node>
  <node id="3" lat="0" lon="0"><tag k="local_x" v="0"/><tag k="local_y" v="3.5"/></node>
  <node id="4" lat="0" lon="0"><tag k="local_x" v="$2"/><tag k="local_y" v="3.5"/></node>
  <way id="10"><nd ref="1"/><nd ref="2"/></way>
  <way id="11"><nd ref="3"/><nd ref="4"/></way>
  <relation id="100"><member type="way" ref="11" role="left"/><member type="way" ref="10" role="right"/>
    <tag k="type" v="lanelet"/><tag k="subtype" v="road"/></relation>
</osm>
XML
    printf 'map m { file "%s.osm" }\nscenario s {\n    road m\n    timeout 1 s\n    object a { start lane "100" at 1 m }\n    expect no_collision()\n}\n' "$1" > "$dir/$1.sdv"
}
map nan_coordinate nan
map far_coordinate 1e300
map long_lanelet 400000
run_check nan_coordinate "$dir/nan_coordinate.sdv" "node 2: local_x / local_y are not numbers"
run_check far_coordinate "$dir/far_coordinate.sdv" "more than 1,000 km from the map's origin"
run_check long_lanelet "$dir/long_lanelet.sdv" "sdv reads lanelets up to 50 km"
python3 -c "print('{\"format\":\"sdvir\",\"version\":1,\"hash\":\"0\",\"program\":' + '[' * 40000 + ']' * 40000 + '}')" > "$dir/deep.sdvir"
run_check deep_ir "$dir/deep.sdvir" "nested more than 64 levels"

# GeoScenario names are data, never .sdv text: a vehicle name with a line break stays in its
# comment, a light name that is no name is refused, and invalid UTF-8 in a name does not break
# `--format json` (issue 22, findings 7 and 8).
gss=$(cd "$(dirname "$0")/../../.." && pwd)/shared/data/geoscenario
if [ -d "$gss" ]; then
    python3 - "$gss/scenarios/trafficlight_red.gs.osm" "$dir" <<'PY'
import sys
src, d = sys.argv[1], sys.argv[2]
s = open(src, encoding="latin-1").read()
open(f"{d}/name_newline.gs.osm", "w", encoding="latin-1").write(
    s.replace("v='red_light_runner'", "v='red&#10;    expect collision(v1)&#10;'"))
open(f"{d}/light_name.gs.osm", "w", encoding="latin-1").write(
    s.replace("k='name' v='tl_e_w'", "k='name' v='tl_e_w { green 1 s } expect collision(v1) light tl_e_w'"))
import re
node = re.search(r"<node id='([-0-9]+)'[^>]*? lon='([^']*)'", s)
open(f"{d}/lon_tail.txt", "w").write(node.group(1))
open(f"{d}/lon_tail.gs.osm", "w", encoding="latin-1").write(
    s.replace(node.group(0), node.group(0).replace("lon='" + node.group(2), "lon='" + node.group(2)[:4] + ":" + node.group(2)[4:])))
open(f"{d}/latin1_name.gs.osm", "w", encoding="latin-1").write(
    s.replace("k='name' v='tl_e_w'", "k='name' v='tl_\xe9_w'"))
PY
    gargs=(--btree-path "$gss/btrees/sdv" --map-dir "$gss/maps")
    "$sdv" convert "$gss/scenarios/trafficlight_red.gs.osm" "${gargs[@]}" -o "$dir/orig.sdv" > /dev/null 2>&1
    if "$sdv" convert "$dir/name_newline.gs.osm" "${gargs[@]}" -o "$dir/nl.sdv" > /dev/null 2>&1 &&
        [ "$(grep -c '^ *expect' "$dir/nl.sdv")" = "$(grep -c '^ *expect' "$dir/orig.sdv")" ] &&
        [ "$(grep -c '^ *expect' "$dir/orig.sdv")" -gt 0 ]; then
        echo "ok   name_newline: a line break in a vehicle name adds no statement"
    else
        echo "FAIL name_newline: the converted scenario gained statements"; fail=1
    fi
    out=$("$sdv" convert "$dir/light_name.gs.osm" "${gargs[@]}" -o "$dir/ln.sdv" 2>&1)
    if [ $? = 1 ] && grep -q "error\[E0911\]: trafficlight name" <<<"$out"; then
        echo "ok   light_name: refused with E0911"
    else
        echo "FAIL light_name: $out" | head -3; fail=1
    fi
    # A coordinate with a tail ('-80.:5...') is no number, not the -80 strtod reads (the node
    # would move tens of kilometres).
    out=$("$sdv" lint "$dir/lon_tail.gs.osm" "${gargs[@]}" 2>&1)
    if [ $? = 1 ] && grep -q "error\[E0911\]: node $(cat "$dir/lon_tail.txt"): lon '[-0-9]*\.:[0-9]*' is not a number" <<<"$out"; then
        echo "ok   lon_tail: refused with E0911 naming the node"
    else
        echo "FAIL lon_tail: $out" | head -3; fail=1
    fi
    "$sdv" lint --format json "$dir/latin1_name.gs.osm" "${gargs[@]}" > "$dir/l1.json" 2> /dev/null
    code=$?
    if [ $code = 1 ] && python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['errors'] >= 1" "$dir/l1.json"; then
        echo "ok   latin1_name: --format json prints valid JSON (exit 1)"
    else
        echo "FAIL latin1_name: exit $code"; head -c 300 "$dir/l1.json"; fail=1
    fi
fi
exit $fail
