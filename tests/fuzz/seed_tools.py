#!/usr/bin/env python3
"""Seed helpers of scripts/fuzz-corpus.sh (tests/fuzz/README.md): turn real inputs into seeds of a
size the fuzzers mutate quickly.

  seed_tools.py record-to-wire RECORD OUT      the client frames of a co-simulation record as the
                                               byte stream of a connection (uint32 LE + payload)
  seed_tools.py truncate-record RECORD N OUT   the header and the first N frames of a record
  seed_tools.py cosim-frames OUT_DIR           hand-made JSON connections: a session, each error
  seed_tools.py sweep-seed SWEEP_DIR OUT       results.csv, a NUL, summary.json (sweep_results)
  seed_tools.py run-seed RUN_DIR TICKS OUT     a run directory's files, NUL between them (run_dir):
                                               trajectories.csv, summary.json, road.json,
                                               decisions.jsonl, recorded.csv, up to the last one
                                               there; the rows and decisions of the first TICKS
                                               ticks only
  seed_tools.py diff-seed RUN_A RUN_B TICKS OUT  two run directories (run_diff): the first's
                                               trajectories.csv and decisions.jsonl, the
                                               second's, NUL between them; the first TICKS
                                               ticks of each. RUN_B "-": the first's alone
                                               (the target compares it with a copy)
  seed_tools.py crop-lanelet2 MAP N OUT_DIR    small maps cut from a Lanelet2 map: N lanelets each,
                                               with their ways, nodes and regulatory elements
"""
import json
import pathlib
import struct
import sys
import xml.etree.ElementTree as ET


def entries(data):
    """(direction, payload) of each complete entry of a record."""
    at = 0
    while at + 5 <= len(data):
        (n,) = struct.unpack_from("<I", data, at + 1)
        if at + 5 + n > len(data):
            return
        yield data[at:at + 1], data[at + 5:at + 5 + n]
        at += 5 + n


def frame(payload):
    return struct.pack("<I", len(payload)) + payload


def record_to_wire(record, out):
    data = pathlib.Path(record).read_bytes()
    pathlib.Path(out).write_bytes(b"".join(frame(p) for d, p in entries(data) if d == b"C"))


def truncate_record(record, n, out):
    data = pathlib.Path(record).read_bytes()
    kept = list(entries(data))[:1 + int(n)]
    pathlib.Path(out).write_bytes(b"".join(d + frame(p) for d, p in kept))


def cosim_frames(out_dir):
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)

    def msg(m):
        return frame(json.dumps(m).encode())

    hello = msg({"seq": 1, "hello": {"protocol": "sdv-cosim", "version_major": 1, "client_name": "seed",
                                     "claims": [{"actor_name": "ego", "mode": "CONTROL_MODE_POSE"}]}})
    state = {"id": "1", "x": 30.0, "y": -1.75, "z": 0.0, "yaw": 0.0, "speed": 10.0, "accel": 0.0,
             "yaw_rate": 0.0}

    def step(seq, tick, **over):
        st = dict(state, x=30.0 + 10.0 / 30 * (tick + 1), **over)
        return msg({"seq": seq, "step": {"tick": tick, "updates": [{"id": "1", "state": st}]}})

    seeds = {
        "json_session": hello + b"".join(step(2 + k, k) for k in range(6)) + msg({"seq": 8, "bye": {"reason": "done"}}),
        "json_bad_tick": hello + step(2, 5),
        "json_nan": hello + step(2, 0, speed="NaN"),
        "json_unknown_actor": hello + msg({"seq": 2, "step": {"tick": 0, "updates": [{"id": "9", "state": state}]}}),
        "json_no_hello": step(1, 0),
        "json_client_error": hello + msg({"seq": 2, "error": {"code": "INTERNAL", "message": "client gave up"}}),
        "json_garbage": hello + frame(b"\x00\xffnot an envelope{"),
        "json_half_frame": hello + struct.pack("<I", 500) + b'{"seq": 2, "st',
        "huge_prefix": struct.pack("<I", 1 << 30) + b"x" * 16,
    }
    for name, data in seeds.items():
        (out / name).write_bytes(data)


def sweep_seed(sweep_dir, out):
    d = pathlib.Path(sweep_dir)
    summary = d / "summary.json"
    data = (d / "results.csv").read_bytes()
    if summary.exists():
        data += b"\0" + summary.read_bytes()
    pathlib.Path(out).write_bytes(data)


RUN_FILES = ["trajectories.csv", "summary.json", "road.json", "decisions.jsonl", "recorded.csv"]


def run_parts(run_dir, ticks, names):
    """The files `names` of a run directory cut to the first `ticks` ticks (None: absent)."""
    d = pathlib.Path(run_dir)
    ticks = int(ticks)
    parts = []
    last_time = 0.0  # of the rows kept: decisions after it are left out
    for name in names:
        f = d / name
        if not f.exists():
            parts.append(None)
            continue
        data = f.read_bytes()
        if name == "trajectories.csv":
            lines = data.splitlines(keepends=True)
            kept = [l for l in lines[1:] if int(l.split(b",")[1]) < ticks]
            last_time = max((float(l.split(b",")[0]) for l in kept), default=0.0)
            data = b"".join(lines[:1] + kept)
        elif name == "decisions.jsonl":
            data = b"".join(l for l in data.splitlines(keepends=True) if json.loads(l)["time"] <= last_time)
        parts.append(data)
    return parts


def run_seed(run_dir, ticks, out):
    parts = run_parts(run_dir, ticks, RUN_FILES)
    while parts and parts[-1] is None:
        parts.pop()
    pathlib.Path(out).write_bytes(b"\0".join(p or b"" for p in parts))


def diff_seed(run_a, run_b, ticks, out):
    names = ["trajectories.csv", "decisions.jsonl"]
    parts = run_parts(run_a, ticks, names) + (run_parts(run_b, ticks, names) if run_b != "-" else [])
    while parts and parts[-1] is None:
        parts.pop()
    pathlib.Path(out).write_bytes(b"\0".join(p or b"" for p in parts))


def crop_lanelet2(path, n, out_dir):
    n = int(n)
    root = ET.parse(path).getroot()
    nodes = {e.get("id"): e for e in root.findall("node")}
    ways = {e.get("id"): e for e in root.findall("way")}
    relations = root.findall("relation")

    def tag(e, k):
        t = e.find(f"tag[@k='{k}']")
        return t.get("v") if t is not None else None

    lanelets = [r for r in relations if tag(r, "type") == "lanelet"]
    regulatory = [r for r in relations if tag(r, "type") == "regulatory_element"]
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    stem = pathlib.Path(path).stem
    for k, first in enumerate(range(0, len(lanelets), max(n, 1) * 8)):
        chosen = lanelets[first:first + n]
        ids = {r.get("id") for r in chosen}
        # Regulatory elements of the chosen lanelets come with them.
        refs = {m.get("ref") for r in chosen for m in r.findall("member") if m.get("type") == "relation"}
        regs = [r for r in regulatory if r.get("id") in refs or
                any(m.get("type") == "relation" and m.get("ref") in ids for m in r.findall("member"))]
        rels = chosen + regs
        way_ids = {m.get("ref") for r in rels for m in r.findall("member") if m.get("type") == "way"}
        node_ids = {m.get("ref") for r in rels for m in r.findall("member") if m.get("type") == "node"}
        for w in way_ids:
            if w in ways:
                node_ids.update(nd.get("ref") for nd in ways[w].findall("nd"))
        osm = ET.Element("osm", root.attrib)
        for i in node_ids:
            if i in nodes:
                osm.append(nodes[i])
        for w in way_ids:
            if w in ways:
                osm.append(ways[w])
        rel_ids = {r.get("id") for r in rels}
        for r in rels:
            r2 = ET.Element(r.tag, r.attrib)
            for c in r:
                if c.tag == "member" and c.get("type") == "relation" and c.get("ref") not in rel_ids:
                    continue
                r2.append(c)
            osm.append(r2)
        ET.ElementTree(osm).write(out / f"{stem}_crop{k}.osm", encoding="UTF-8", xml_declaration=True)
        if k >= 5:
            break


if __name__ == "__main__":
    cmd, args = sys.argv[1], sys.argv[2:]
    {"record-to-wire": record_to_wire, "truncate-record": truncate_record, "cosim-frames": cosim_frames,
     "sweep-seed": sweep_seed, "run-seed": run_seed, "diff-seed": diff_seed, "crop-lanelet2": crop_lanelet2}[cmd](*args)
