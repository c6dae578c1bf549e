"""The Python package (python/sdv) over libsdv.so: errors raise sdv.Error with the C status and
message, a run drives the external ego to the end, and two simulations in one process give the
same run (no global state).  python3 python_test.py LIBSDV SCENARIO OUTDIR"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "python"))
os.environ["SDV_LIBRARY"] = sys.argv[1]
import sdv  # noqa: E402

scenario, out = sys.argv[2], sys.argv[3]
assert sdv.version().startswith("sdv "), sdv.version()

try:
    sdv.Simulation("/nonexistent.sdv")
    raise AssertionError("a missing scenario loaded")
except sdv.Error as e:
    assert e.status == sdv.ERR_SCENARIO and "/nonexistent.sdv" in e.message, e


class Keeper:
    """Keeps the ego's speed and lane (a yaw rate against the lane offset and its rate)."""

    def __init__(self, sim, ego):
        self.sim, self.ego, self.last_d = sim, ego, None

    def __call__(self):
        me = self.sim.states()[self.ego - 1]
        last = me.d if self.last_d is None else self.last_d
        yaw = me.yaw + (-0.4 * me.d - 1.2 * (me.d - last) * 30) / 30
        self.last_d = me.d
        self.sim.set_state(self.ego, x=me.x + me.speed * math.cos(yaw) / 30, y=me.y + me.speed * math.sin(yaw) / 30,
                           yaw=yaw, speed=me.speed)


with sdv.Simulation(scenario, output_dir=out) as a, sdv.Simulation(scenario) as b:
    assert [x.name for x in a.actors()] == ["ego", "v2"], a.actors()
    try:
        a.claim("v2")
        raise AssertionError("claimed an SDV")
    except sdv.Error as e:
        assert e.status == sdv.ERR_NOT_FOUND, e
    ego = a.claim("ego")
    assert b.claim("ego") == ego == 1
    try:
        a.step()
        raise AssertionError("stepped without the ego's state")
    except sdv.Error as e:
        assert e.status == sdv.ERR_STATE and "ego" in e.message, e
    events = []
    keep_a, keep_b = Keeper(a, ego), Keeper(b, ego)
    while a.run_state == sdv.RUNNING:
        keep_a()
        keep_b()
        a.step()
        b.step()
        events += a.events()
        sa, sb = a.states(), b.states()
        assert [(s.x, s.y, s.speed) for s in sa] == [(s.x, s.y, s.speed) for s in sb], (a.tick, sa, sb)
    assert a.tick == 900 and abs(a.time - 30.0) < 1e-12, (a.tick, a.time)
    assert events[-1].type == sdv.EVENT_SCENARIO_END, events[-1].text
    assert any(e.type == sdv.EVENT_MANEUVER and e.a == 2 for e in events)
    a.finish()
print("python package: ok;", len(events), "events; outputs in", out)
