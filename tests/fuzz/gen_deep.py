#!/usr/bin/env python3
"""Seeds that a fuzzer with a small -max_len never reaches on its own: deep nesting and long
inputs for every reader (tests/fuzz/README.md). Writes OUT_DIR/<target>/deep_*:

  gen_deep.py OUT_DIR

Each reader must answer such an input quickly with a located error or a result, never with a
crash, a hang or memory in proportion to something other than the input's size.
"""
import json
import pathlib
import sys

out = pathlib.Path(sys.argv[1])

SCENARIO = """import "std/drive.sdv"

road two_lanes {{
    lanes 2 forward
    lane_width 3.5 m
    speed_limit 60 km/h
    straight 800 m
}}

tree t(speed: speed = 14 m/s) {{
    fallback {{
{tree}
        maneuver keep_velocity(speed = speed)
    }}
}}

scenario deep {{
    road two_lanes
    timeout 20 s
    ego a: sdv {{
        start lane 1 at 20 m
        speed 14 m/s
        tree t()
    }}
    vehicle b: sdv {{
        start lane 1 at 60 m
        speed 14 m/s
        tree std.drive(speed = 12 m/s)
    }}
    expect {expect}
}}
"""


def sdv(tree="", expect="no_collision()"):
    return SCENARIO.format(tree=tree, expect=expect)


def write(target, name, data):
    d = out / target
    d.mkdir(parents=True, exist_ok=True)
    (d / f"deep_{name}").write_bytes(data.encode() if isinstance(data, str) else data)


# .sdv: binary operators, unary operators, parentheses and braces nested far beyond any limit;
# long lines, names, strings, numbers and comments.
write("sdv_frontend", "and_chain_8000.sdv", sdv(expect=" and ".join(["no_collision()"] * 8000)))
write("sdv_frontend", "or_chain_8000_short.sdv", sdv(expect=" or ".join(["x"] * 8000)))
write("sdv_frontend", "not_chain_10000.sdv", sdv(expect="not " * 10000 + "timeout()"))
write("sdv_frontend", "parens_10000.sdv", sdv(expect="(" * 10000 + "no_collision()" + ")" * 10000))
write("sdv_frontend", "minus_chain_20000.sdv",
      sdv(tree="        maneuver keep_velocity(speed = " + "-" * 20000 + "1 m/s)"))
write("sdv_frontend", "sequence_5000.sdv",
      sdv(tree="sequence {\n" * 5000 + "maneuver keep_velocity(speed = 1 m/s)\n" + "}\n" * 5000))
write("sdv_frontend", "long_comment_100k.sdv", "# " + "x" * 100000 + "\n" + sdv())
write("sdv_frontend", "long_name_60k.sdv", sdv(expect="min_gap(a, b) > 5 m and " + "n" * 60000 + "()"))
write("sdv_frontend", "long_string_60k.sdv", 'import "' + "s" * 60000 + '"\n' + sdv())
write("sdv_frontend", "long_number_60k.sdv",
      sdv(tree="        maneuver keep_velocity(speed = 1" + "0" * 60000 + " m/s)"))
write("sdv_frontend", "many_expects_800.sdv", sdv(expect="\n    expect ".join(["no_collision()"] * 800)))

# .btree: nested parentheses in an argument, deep indentation, long lines.
BT = "behaviortree deep:\n    ?\n{body}        maneuver m_keep(MVelKeepConfig(vel=MP(14.0,10,6)))\n"
write("btree", "parens_30k.btree",
      "behaviortree deep:\n    maneuver m_keep(MVelKeepConfig(vel=" + "(" * 15000 + "14.0" + ")" * 15000 + "))\n")
write("btree", "call_nesting_5000.btree",
      "behaviortree deep:\n    maneuver m_keep(" + "MP(" * 5000 + "1" + ")" * 5000 + ")\n")
# 150 levels, past the limit of 128, within the target's 64 KB.
write("btree", "indent_150.btree",
      "behaviortree deep:\n" + "".join("    " * (k + 1) + "->\n" for k in range(150))
      + "    " * 151 + "maneuver m_keep(MVelKeepConfig(vel=MP(14.0,10,6)))\n")
write("btree", "long_line_60k.btree",
      BT.format(body="        condition c_x(" + "a" * 60000 + "=1)\n"))
write("btree", "many_args_5000.btree",
      "behaviortree deep:\n    maneuver m_keep(MVelKeepConfig(" + ",".join(f"p{k}={k}" for k in range(5000)) + "))\n")

# .gs.osm: many elements, long names and values, deep XML.
nodes = "".join(f"  <node id='-{k}' lat='49.0{k:05d}' lon='8.45'/>\n" for k in range(1, 1001))
write("gss_scenario", "route_1000.gs.osm",
      "<?xml version='1.0' encoding='UTF-8'?>\n<osm version='0.6'>\n"
      "  <node id='-90000' lat='49.0' lon='8.45'><tag k='gs' v='globalconfig'/><tag k='lanelet' v='map.osm'/>"
      "<tag k='name' v='deep'/><tag k='version' v='2.0'/><tag k='timeout' v='10'/></node>\n"
      "  <node id='-90001' lat='49.0' lon='8.45'><tag k='gs' v='origin'/></node>\n"
      "  <node id='-90002' lat='49.0' lon='8.45'><tag k='gs' v='vehicle'/><tag k='btype' v='SDV'/>"
      "<tag k='vid' v='1'/><tag k='name' v='v1'/><tag k='btree' v='drive.btree'/><tag k='route' v='r'/></node>\n"
      + nodes + "  <way id='-1'>" + "".join(f"<nd ref='-{k}'/>" for k in range(1, 1001))
      + "<tag k='gs' v='route'/><tag k='name' v='r'/></way>\n</osm>\n")
write("gss_scenario", "xml_depth_9000.gs.osm", "<osm>" + "<x>" * 9000 + "</x>" * 9000 + "</osm>")  # within 64 KB
write("gss_scenario", "long_name_60k.gs.osm",
      "<osm><node id='1' lat='49' lon='8'><tag k='gs' v='globalconfig'/><tag k='lanelet' v='m.osm'/>"
      "<tag k='name' v='" + "n" * 60000 + "'/></node></osm>")

# Lanelet2: a very long lanelet (its reference line), many tiny ones, deep XML, odd numbers.
def lanelet_map(left, right, extra_tags=""):
    nodes = []
    k = 0
    for line in (left, right):
        for x, y in line:
            k += 1
            nodes.append(f'<node id="{k}"><tag k="local_x" v="{x}"/><tag k="local_y" v="{y}"/></node>')
    n = len(left)
    way = lambda first, count, wid: f'<way id="{wid}">' + "".join(f'<nd ref="{first + i}"/>' for i in range(count)) + "</way>"
    return ('<osm>' + "".join(nodes) + way(1, n, 100001) + way(n + 1, len(right), 100002)
            + '<relation id="100003"><member type="way" ref="100001" role="left"/>'
            '<member type="way" ref="100002" role="right"/><tag k="type" v="lanelet"/>'
            f'<tag k="subtype" v="road"/>{extra_tags}</relation></osm>')


write("lanelet2", "long_lanelet_900km.osm", lanelet_map([(0, 0), (9e5, 0)], [(0, -3), (9e5, -3)]))
write("lanelet2", "long_lanelet_1e300.osm", lanelet_map([(0, 0), ("1e300", 0)], [(0, -3), ("1e300", -3)]))
write("lanelet2", "nan_node.osm", lanelet_map([(0, 0), ("nan", 0)], [(0, -3), (10, -3)]))
write("lanelet2", "points_4000.osm",
      lanelet_map([(k * 0.01, 0) for k in range(2000)], [(k * 0.01, -3) for k in range(2000)]))
write("lanelet2", "xml_depth_20000.osm", "<osm>" + "<x>" * 20000 + "</x>" * 20000 + "</osm>")

# IR: JSON nested deep in every place a value may be, long strings, many elements.
def ir(program):
    return '{"format":"sdvir","version":1,"compiler":"sdv 0.1.0","hash":"0000000000000000","program":' + program + "}"


write("ir_reader", "arrays_40000.sdvir", ir("[" * 40000 + "]" * 40000))
write("ir_reader", "objects_20000.sdvir", ir('{"a":' * 20000 + "0" + "}" * 20000))
write("ir_reader", "hash_first_arrays_40000.sdvir",
      '{"hash":"0000000000000000","format":"sdvir","version":1,"program":' + "[" * 40000 + "]" * 40000 + "}")
write("ir_reader", "long_string_100k.sdvir", ir(json.dumps({"trees": [], "name": "x" * 100000})))
write("ir_reader", "numbers.sdvir", ir(json.dumps({"trees": [1e308, -1e308, 5e-324, 2**64, -2**63]})))

# Co-simulation: a frame nested deep in JSON, a long one, many tiny ones.
def frame(payload):
    return len(payload).to_bytes(4, "little") + payload


write("cosim_frame", "json_depth_20000", frame(b'{"hello":' + b"[" * 20000 + b"]" * 20000 + b"}"))
write("cosim_frame", "json_long_name_100k",
      frame(json.dumps({"seq": 1, "hello": {"protocol": "sdv-cosim", "version_major": 1,
                                            "client_name": "c" * 100000}}).encode()))
write("cosim_frame", "binary_nested_groups", frame(b"\x0b" * 30000 + b"\x0c" * 30000))
write("cosim_frame", "empty_frames_1000", frame(b"") * 1000)
write("cosim_frame", "record_json_depth",
      b"H" + frame(b'{"format":"sdv-cosim-record","version":1,"encoding":"json","x":' + b"[" * 20000 + b"]" * 20000 + b"}"))

# Sweep directories: many rows, long cells, deep summary.json.
header = "variant,speed,gap,passed,error\n"
write("sweep_results", "rows_5000", header + "".join(f"{k},{k % 50},{k // 50},{k % 3 != 0},\n" for k in range(5000))
      + "\0" + json.dumps({"format": "sdv-sweep/1", "variants": 5000}))
write("sweep_results", "long_cell_100k", header + "0,1,2,true," + "e" * 100000 + "\n\0{}")
write("sweep_results", "summary_depth_20000", header + "0,1,2,true,\n\0" + "[" * 20000 + "]" * 20000)

# Run directories (trajectories.csv, summary.json, road.json, decisions.jsonl, recorded.csv):
# many rows and vehicles, long cells, deep JSON, a tick far beyond any run.
traj = "time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver\n"
summary = json.dumps({"scenario": "deep", "ticks": 3000, "passed": True})
rows = "".join(f"{k // 100 / 30:.4f},{k // 100},v{k % 100},sdv,{k * 0.1:.4f},0.0000,0.0000,10.0000,0.0000,{k * 0.1:.4f},0.0000,a.1,keep\n"
               for k in range(3000))
write("run_dir", "rows_3000_vehicles_100", traj + rows + "\0" + summary)
write("run_dir", "long_name_100k", traj + "0.0000,0," + "v" * 100000 + ",sdv,0,0,0,0,0,0,0,a.1,keep\n\0" + summary)
write("run_dir", "tick_far_beyond_rows", traj + "0.0000,99999999,v,sdv,0,0,0,0,0,0,0,a.1,keep\n\0" + summary)
write("run_dir", "summary_depth_20000", traj + "0.0000,0,v,sdv,0,0,0,0,0,0,0,a.1,keep\n\0" + "[" * 20000 + "]" * 20000)
write("run_dir", "road_depth_20000", traj + "0.0000,0,v,sdv,0,0,0,0,0,0,0,a.1,keep\n\0" + summary + "\0"
      + '{"lanes":' + "[" * 20000 + "]" * 20000 + "}")
write("run_dir", "decisions_1000", traj + "0.0000,0,v,sdv,0,0,0,0,0,0,0,a.1,keep\n\0" + summary + "\0{}\0"
      + "".join(json.dumps({"time": k / 10, "vehicle": "v", "nodes": [{"node": f"t/n{k % 7}", "status": "SUCCESS"}],
                            "rejected": {"collision": k}, "paths": [{"status": "ok", "xy": [k] * 12}]}) + "\n"
                for k in range(1000)))

# Pairs of run directories (sdv diff --runs: the first's trajectories.csv and decisions.jsonl,
# the second's): many rows differing late, ticks at and beyond the highest of any run, a long
# name, deep and many decisions.
rows_a = "".join(rows.splitlines(keepends=True)[:1200])  # both runs within -max_len (256 KB)
rows_b = rows_a[:-200] + rows_a[-200:].replace("119.9000", "119.8000")  # the last row's x
row = "0.0000,{tick},v,sdv,0,0,0,0,0,0,0,a.1,keep\n"
write("run_diff", "rows_1200_differ_last", traj + rows_a + "\0\0" + traj + rows_b)
write("run_diff", "tick_highest_of_any_run", traj + row.format(tick=86400000) + "\0\0" + traj + row.format(tick=86400001))
write("run_diff", "long_name_100k", traj + "0.0000,0," + "v" * 100000 + ",sdv,0,0,0,0,0,0,0,a.1,keep\n")
write("run_diff", "decisions_depth_20000", traj + row.format(tick=0) + "\0" + '{"time":0,"vehicle":"v","cost":' + "[" * 20000
      + "]" * 20000 + "}")
decisions = "".join(json.dumps({"time": k / 10, "vehicle": f"v{k % 3}", "maneuver": "keep", "winner": k % 6,
                                "cost": {"total": k / 7}}) + "\n" for k in range(1000))
write("run_diff", "decisions_1000_last_differs", traj + row.format(tick=0) + "\0" + decisions + "\0" + traj + row.format(tick=0)
      + "\0" + decisions.replace('"winner": 3, "cost": {"total": 142.714', '"winner": 2, "cost": {"total": 142.714'))

# A sweep's rows (the campaign of tests/fuzz/targets/sweep_rows.sdv), within the target's 8 KB
# (scripts/fuzz.sh): one row a hundred times, a long error, a line of commas, a quote never
# closed. Larger files of the kind are in its committed corpus, replayed in every build.
sweep_row = "0,302,7.81939,135.263,1,,0,42.4809,118.019,118.019,0,1,118.019,1,,1\n"
write("sweep_rows", "same_row_100", sweep_row * 100)
write("sweep_rows", "error_8000", '0,302,7.81939,135.263,0,"' + "e" * 8000 + '",,,,,,,,0,,0\n')
write("sweep_rows", "commas_8000", "," * 8000 + "\n")
write("sweep_rows", "open_quote_8000", '0,302,"' + "x," * 4000 + "\n" + sweep_row)
