#!/usr/bin/env python3
"""A stand-in automated driving system that drives sdv's external ego: the reference client.

It is a client of "sdv-cosim v1" (docs/cosim.md) in the protocol's JSON encoding with the
standard library only, or in the binary encoding with python3-protobuf, or in process through the
C API (python/sdv). Every step it reads the observation at k, decides, and sends the ego's state
at k+1. Its driving is deliberately simple and its own (sdv plans nothing for it):

- longitudinal: the Intelligent Driver Model (Treiber et al. 2000) behind the nearest vehicle
  ahead in its path; "in its path" is judged geometrically (the other's box against the ego's
  path bent with its current curvature), so a car cutting in counts as soon as it overlaps;
- lateral: lane keeping on the observed lane, a yaw rate against the lateral offset d from the
  lane's centre and its rate;
- kinematics: a unicycle integrated over the step (1/30 s).

    sdv run examples/cosim/cut_in.sdv --cosim tcp://127.0.0.1:0 --cosim-port-file port \\
        --cosim-encoding json -o out/cosim &
    python3 examples/cosim/ads_client.py --port-file port
    python3 examples/cosim/ads_client.py --in-process examples/cosim/cut_in.sdv -o out/inproc

The same driver gives the same run whichever way it connects (tests/unit/cosim: equivalence).
"""

import argparse
import json
import math
import os
import socket
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def number_ids(actor):
    """An actor of either encoding as a dict with an integer id (JSON carries uint64 as text)."""
    return dict(actor, id=int(actor["id"]))


class Network:
    """A session over TCP or a Unix socket: length-prefixed frames (uint32 little-endian)."""

    def __init__(self, address, encoding, wait_s=30.0):
        deadline = time.monotonic() + wait_s
        while True:
            try:
                if address.startswith("unix:"):
                    self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                    self.sock.connect(address[len("unix:"):])
                else:
                    host, port = address[len("tcp://"):].rsplit(":", 1)
                    self.sock = socket.create_connection((host, int(port)))
                    self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.05)
        self.seq = 0
        self.pb = protobuf_module() if encoding == "binary" else None

    def _send(self, body):
        self.seq += 1
        if self.pb is None:
            data = json.dumps(dict(body, seq=str(self.seq))).encode()
        else:
            from google.protobuf import json_format
            env = json_format.ParseDict(dict(body, seq=str(self.seq)), self.pb.Envelope())
            data = env.SerializeToString()
        self.sock.sendall(struct.pack("<I", len(data)) + data)

    def _read(self, n):
        buf = b""
        while len(buf) < n:
            chunk = self.sock.recv(n - len(buf))
            if not chunk:
                raise ConnectionError("the server closed the connection")
            buf += chunk
        return buf

    def _receive(self):
        (n,) = struct.unpack("<I", self._read(4))
        data = self._read(n)
        if self.pb is None:
            msg = json.loads(data)
        else:
            from google.protobuf import json_format
            env = self.pb.Envelope()
            env.ParseFromString(data)
            msg = json_format.MessageToDict(env, preserving_proto_field_name=True, including_default_value_fields=True)
        if "error" in msg:
            raise RuntimeError(f"server error {msg['error'].get('code')}: {msg['error'].get('message')}")
        return msg

    def start(self, actor):
        self._send({"hello": {"protocol": "sdv-cosim", "version_major": 1, "version_minor": 0, "client_name": "ads_client.py",
                              "claims": [{"actor_name": actor, "mode": "CONTROL_MODE_POSE"}]}})
        w = self._receive()["welcome"]
        infos = {int(a["id"]): a for a in w["actors"]}
        me = next(i for i, a in infos.items() if a["name"] == actor)
        obs = w["initial"]
        return infos, me, w["step_num"] / w["step_den"], int(obs["tick"]), [number_ids(a) for a in obs["actors"]]

    def step(self, tick, state):
        self._send({"step": {"tick": str(tick), "updates": [{"id": str(state["id"]), "state": dict(state, id=str(state["id"]))}]}})
        r = self._receive()["step_result"]
        events = ["collision" for e in r.get("events", []) if "collision" in e]
        obs = r["observation"]
        return int(obs["tick"]), [number_ids(a) for a in obs["actors"]], events, r["run_state"]

    def close(self):
        self._send({"bye": {"reason": "scenario ended"}})
        self.sock.close()


class InProcess:
    """The same session through the C API (python/sdv over libsdv.so), no socket."""

    NAMES = {1: "RUNNING", 2: "ENDED_SUCCESS", 3: "ENDED_FAILURE", 4: "ENDED_TIMEOUT"}

    def __init__(self, scenario, output_dir):
        sys.path.insert(0, os.path.join(ROOT, "python"))
        import sdv
        self.sdv = sdv
        self.sim = sdv.Simulation(scenario, output_dir=output_dir)

    def _actors(self):
        return [{"id": a.id, "x": a.x, "y": a.y, "yaw": a.yaw, "speed": a.speed, "accel": a.accel, "yaw_rate": a.yaw_rate,
                 "lane_id": a.lane_id, "s": a.s, "d": a.d, "active": bool(a.active)} for a in self.sim.states()]

    def start(self, actor):
        me = self.sim.claim(actor)
        infos = {a.id: {"name": a.name, "length": a.length, "width": a.width} for a in self.sim.actors()}
        return infos, me, 1.0 / 30, self.sim.tick, self._actors()

    def step(self, tick, state):
        assert tick == self.sim.tick
        self.sim.set_state(state["id"], x=state["x"], y=state["y"], yaw=state["yaw"], speed=state["speed"],
                           accel=state["accel"], yaw_rate=state["yaw_rate"])
        rs = self.sim.step()
        events = ["collision" for e in self.sim.events() if e.type == self.sdv.EVENT_COLLISION]
        return self.sim.tick, self._actors(), events, self.NAMES[rs]

    def close(self):
        self.sim.finish()
        self.sim.close()


def protobuf_module():
    """sdv_cosim_pb2, generated from the repository's schema with protoc when not importable."""
    try:
        import sdv_cosim_pb2
        return sdv_cosim_pb2
    except ImportError:
        pass
    out = tempfile.mkdtemp(prefix="sdv_cosim_pb2_")
    proto_dir = os.path.join(ROOT, "runtime", "cosim")
    subprocess.run(["protoc", f"--proto_path={proto_dir}", f"--python_out={out}", os.path.join(proto_dir, "sdv_cosim.proto")],
                   check=True)
    sys.path.insert(0, out)
    import sdv_cosim_pb2
    return sdv_cosim_pb2


class Driver:
    """IDM car following and lane keeping for one vehicle."""

    def __init__(self, me_info, infos, desired_speed, dt):
        self.me_info, self.infos, self.v0, self.dt = me_info, infos, desired_speed, dt
        self.last_d = None
        # IDM parameters: time headway, minimum gap, max acceleration, comfortable braking.
        self.T, self.s0, self.a, self.b = 1.5, 2.0, 2.0, 3.0

    def leader(self, me, actors):
        """The nearest actor whose box overlaps the ego's path ahead: (bumper gap, its speed)."""
        kappa = me["yaw_rate"] / me["speed"] if me["speed"] > 1.0 else 0.0
        c, s = math.cos(me["yaw"]), math.sin(me["yaw"])
        best = None
        for o in actors:
            if o["id"] == me["id"] or not o.get("active", True):
                continue
            dx, dy = o["x"] - me["x"], o["y"] - me["y"]
            ahead, side = dx * c + dy * s, -dx * s + dy * c
            if ahead <= 0:
                continue
            info = self.infos[o["id"]]
            half = 0.5 * (self.me_info["width"] + info["width"]) + 0.3
            if abs(side - 0.5 * kappa * ahead * ahead) > half:
                continue
            gap = ahead - 0.5 * (self.me_info["length"] + info["length"])
            if best is None or gap < best[0]:
                best = (gap, o["speed"] * math.cos(o["yaw"] - me["yaw"]))
        return best

    def next_state(self, me, actors):
        v = me["speed"]
        acc = self.a * (1 - (v / self.v0) ** 4)
        lead = self.leader(me, actors)
        if lead is not None:
            gap, v_lead = lead
            want = self.s0 + max(0.0, v * self.T + v * (v - v_lead) / (2 * math.sqrt(self.a * self.b)))
            acc -= self.a * (want / max(gap, 0.1)) ** 2
        acc = max(-9.0, acc)
        d = me["d"] if me.get("lane_id") else 0.0
        d_rate = 0.0 if self.last_d is None else (d - self.last_d) / self.dt
        self.last_d = d
        yaw_rate = -0.4 * d - 1.2 * d_rate
        yaw = me["yaw"] + yaw_rate * self.dt
        v_next = max(0.0, v + acc * self.dt)
        step = 0.5 * (v + v_next) * self.dt
        return {"id": me["id"], "x": me["x"] + step * math.cos(yaw), "y": me["y"] + step * math.sin(yaw),
                "z": 0.0, "yaw": yaw, "speed": v_next, "accel": (v_next - v) / self.dt, "yaw_rate": yaw_rate,
                "active": True}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--connect", help="tcp://HOST:PORT or unix:PATH")
    ap.add_argument("--port-file", help="read the TCP port sdv chose (sdv run --cosim-port-file)")
    ap.add_argument("--encoding", choices=["json", "binary"], default="json", help="as sdv's --cosim-encoding")
    ap.add_argument("--in-process", metavar="SCENARIO", help="run SCENARIO through the C API instead of a socket")
    ap.add_argument("-o", "--output", help="with --in-process: the run's output directory")
    ap.add_argument("--actor", default="ego", help="the external vehicle to drive")
    ap.add_argument("--speed", type=float, default=13.9, help="desired speed (m/s)")
    args = ap.parse_args()
    if args.in_process:
        session = InProcess(args.in_process, args.output)
    else:
        address = args.connect
        if args.port_file:
            deadline = time.monotonic() + 30
            while not os.path.exists(args.port_file) and time.monotonic() < deadline:
                time.sleep(0.05)
            port = open(args.port_file).read().strip()
            address = port if port.startswith("unix:") or port.startswith("/") else f"tcp://127.0.0.1:{port}"
            if address.startswith("/"):
                address = "unix:" + address
        if not address:
            ap.error("give --connect, --port-file or --in-process")
        session = Network(address, args.encoding)

    infos, me_id, dt, tick, actors = session.start(args.actor)
    driver = Driver(infos[me_id], infos, args.speed, dt)
    collisions, run_state = 0, "RUNNING"
    while run_state == "RUNNING":
        me = next(a for a in actors if a["id"] == me_id)
        tick, actors, events, run_state = session.step(tick, driver.next_state(me, actors))
        collisions += len(events)
    session.close()
    print(f"{args.actor} driven to tick {tick} ({tick * dt:.2f} s): {run_state}, {collisions} collisions")
    return 0 if run_state == "ENDED_SUCCESS" else 1


if __name__ == "__main__":
    sys.exit(main())
