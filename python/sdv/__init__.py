"""sdv's in-process C API (include/sdv/sdv.h) for Python: ctypes over libsdv.so, stdlib only.

    import sdv
    with sdv.Simulation("examples/cosim/cut_in.sdv", output_dir="out/py") as sim:
        ego = sim.claim("ego")
        while sim.run_state == sdv.RUNNING:
            me = sim.states()[ego - 1]
            sim.set_state(ego, x=me.x + me.speed / 30, y=me.y, yaw=me.yaw, speed=me.speed)
            sim.step()
        sim.finish()

The library is found through $SDV_LIBRARY, else next to this package's checkout (build/*/libsdv.so),
else by the system's loader. Errors raise sdv.Error with the C API's status and message.
See docs/cosim.md.
"""

import ctypes
import glob
import math
import os

API_VERSION = 1000

OK, ERR_ARG, ERR_STATE, ERR_NOT_FOUND, ERR_SCENARIO, ERR_BUFFER, ERR_UNSUPPORTED, ERR_INTERNAL = 0, -1, -2, -3, -4, -5, -6, -99
RUNNING, ENDED_SUCCESS, ENDED_FAILURE, ENDED_TIMEOUT = 1, 2, 3, 4
CONTROL_POSE, CONTROL_COMMAND = 1, 2
KIND_CAR, KIND_TRUCK, KIND_PEDESTRIAN, KIND_CYCLIST, KIND_OBJECT = 1, 2, 3, 4, 5
EVENT_COLLISION, EVENT_SCENARIO_END, EVENT_MANEUVER = 1, 2, 3
FLAG_SEED, FLAG_TRACE = 1, 2

_STATUS_NAMES = {ERR_ARG: "ERR_ARG", ERR_STATE: "ERR_STATE", ERR_NOT_FOUND: "ERR_NOT_FOUND",
                 ERR_SCENARIO: "ERR_SCENARIO", ERR_BUFFER: "ERR_BUFFER",
                 ERR_UNSUPPORTED: "ERR_UNSUPPORTED", ERR_INTERNAL: "ERR_INTERNAL"}


class Error(Exception):
    """A C API call failed: `status` is its sdv_status, the message sdv_last_error's."""

    def __init__(self, status, message):
        super().__init__(f"{_STATUS_NAMES.get(status, status)}: {message}")
        self.status = status
        self.message = message


class _Config(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32), ("scenario_path", ctypes.c_char_p),
                ("scenario_name", ctypes.c_char_p), ("output_dir", ctypes.c_char_p),
                ("seed", ctypes.c_uint64), ("step_num", ctypes.c_uint32), ("step_den", ctypes.c_uint32),
                ("flags", ctypes.c_uint32), ("threads", ctypes.c_int32)]


class ActorState(ctypes.Structure):
    """sdv_actor_state: box centre x, y, z (m), yaw (rad), speed, accel, yaw_rate, lane s and d."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("id", ctypes.c_uint64),
                ("x", ctypes.c_double), ("y", ctypes.c_double), ("z", ctypes.c_double),
                ("yaw", ctypes.c_double), ("speed", ctypes.c_double), ("accel", ctypes.c_double),
                ("yaw_rate", ctypes.c_double), ("s", ctypes.c_double), ("d", ctypes.c_double),
                ("_lane_id", ctypes.c_char * 32), ("active", ctypes.c_int32)]

    @property
    def lane_id(self):
        return self._lane_id.decode()

    def __repr__(self):
        return (f"ActorState(id={self.id}, x={self.x:.3f}, y={self.y:.3f}, yaw={self.yaw:.4f}, "
                f"speed={self.speed:.3f}, lane_id={self.lane_id!r}, s={self.s:.3f}, d={self.d:.3f})")


class ActorInfo(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32), ("id", ctypes.c_uint64), ("_name", ctypes.c_char * 64),
                ("kind", ctypes.c_int32), ("external", ctypes.c_int32), ("length", ctypes.c_double),
                ("width", ctypes.c_double), ("height", ctypes.c_double), ("bbcenter_to_rear_x", ctypes.c_double)]

    @property
    def name(self):
        return self._name.decode()


class Event(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32), ("tick", ctypes.c_uint64), ("type", ctypes.c_int32),
                ("a", ctypes.c_uint64), ("b", ctypes.c_uint64), ("_text", ctypes.c_char * 96)]

    @property
    def text(self):
        return self._text.decode()


def _find_library():
    env = os.environ.get("SDV_LIBRARY")
    if env:
        return env
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    for preset in ("release", "dev", "ci", "asan"):
        path = os.path.join(root, "build", preset, "libsdv.so")
        if os.path.exists(path):
            return path
    found = sorted(glob.glob(os.path.join(root, "build", "*", "libsdv.so")))
    return found[0] if found else "libsdv.so"


_lib = None


def library():
    """The loaded libsdv.so (checked against this package's API major version)."""
    global _lib
    if _lib is not None:
        return _lib
    lib = ctypes.CDLL(_find_library())
    P = ctypes.POINTER
    sim = ctypes.c_void_p
    sigs = {
        "sdv_api_version": ([], ctypes.c_uint32),
        "sdv_version_string": ([], ctypes.c_char_p),
        "sdv_create": ([P(_Config), P(sim)], ctypes.c_int),
        "sdv_destroy": ([sim], None),
        "sdv_last_error": ([sim], ctypes.c_char_p),
        "sdv_claim": ([sim, ctypes.c_char_p, ctypes.c_int, P(ctypes.c_uint64)], ctypes.c_int),
        "sdv_get_actor_info": ([sim, P(ActorInfo), ctypes.c_size_t, P(ctypes.c_size_t)], ctypes.c_int),
        "sdv_set_external_state": ([sim, P(ActorState)], ctypes.c_int),
        "sdv_step": ([sim, P(ctypes.c_int)], ctypes.c_int),
        "sdv_get_tick": ([sim, P(ctypes.c_uint64), P(ctypes.c_double)], ctypes.c_int),
        "sdv_get_actor_states": ([sim, P(ActorState), ctypes.c_size_t, P(ctypes.c_size_t)], ctypes.c_int),
        "sdv_poll_events": ([sim, P(Event), ctypes.c_size_t, P(ctypes.c_size_t)], ctypes.c_int),
        "sdv_finish": ([sim], ctypes.c_int),
        "sdv_passed": ([sim, P(ctypes.c_int32)], ctypes.c_int),
    }
    for name, (args, res) in sigs.items():
        fn = getattr(lib, name)
        fn.argtypes = args
        fn.restype = res
    if lib.sdv_api_version() // 1000 != API_VERSION // 1000:
        raise ImportError(f"libsdv.so has API version {lib.sdv_api_version()}, this package {API_VERSION}")
    _lib = lib
    return lib


def version():
    return library().sdv_version_string().decode()


class Simulation:
    """One simulation of one scenario (an sdv_sim handle). Several may live in one process."""

    def __init__(self, scenario_path, scenario_name=None, output_dir=None, seed=None, threads=1, trace=False):
        lib = library()
        cfg = _Config(ctypes.sizeof(_Config), os.fsencode(scenario_path),
                      scenario_name.encode() if scenario_name else None,
                      os.fsencode(output_dir) if output_dir else None,
                      seed or 0, 0, 0, (FLAG_SEED if seed is not None else 0) | (FLAG_TRACE if trace else 0), threads)
        self._h = ctypes.c_void_p()
        status = lib.sdv_create(ctypes.byref(cfg), ctypes.byref(self._h))
        if status != OK:
            message = lib.sdv_last_error(self._h).decode()
            lib.sdv_destroy(self._h)
            self._h = None
            raise Error(status, message)
        self.run_state = RUNNING

    def _check(self, status):
        if status != OK:
            raise Error(status, library().sdv_last_error(self._h).decode())

    def claim(self, actor_name, mode=CONTROL_POSE):
        """Takes control of an external vehicle; returns its id."""
        out = ctypes.c_uint64()
        self._check(library().sdv_claim(self._h, actor_name.encode(), mode, ctypes.byref(out)))
        return out.value

    def _array(self, fn, kind):
        n = ctypes.c_size_t()
        status = fn(self._h, None, 0, ctypes.byref(n))
        if status not in (OK, ERR_BUFFER):
            self._check(status)
        buf = (kind * max(1, n.value))()
        self._check(fn(self._h, buf, len(buf), ctypes.byref(n)))
        return list(buf[:n.value])

    def actors(self):
        return self._array(library().sdv_get_actor_info, ActorInfo)

    def states(self):
        """Every actor at the current tick, sorted by id (id = index + 1)."""
        return self._array(library().sdv_get_actor_states, ActorState)

    def set_state(self, actor_id, x, y, yaw, speed, accel=0.0, z=0.0, yaw_rate=0.0, active=True):
        """The state of a claimed actor at the next tick."""
        for v in (x, y, yaw, speed, accel, z, yaw_rate):
            if not math.isfinite(v):
                raise Error(ERR_ARG, "non-finite value")
        st = ActorState(ctypes.sizeof(ActorState), actor_id, x, y, z, yaw, speed, accel, yaw_rate, 0.0, 0.0,
                        b"", 1 if active else 0)
        self._check(library().sdv_set_external_state(self._h, ctypes.byref(st)))

    def step(self):
        """k -> k+1; returns the run state (RUNNING until the scenario ends)."""
        rs = ctypes.c_int()
        self._check(library().sdv_step(self._h, ctypes.byref(rs)))
        self.run_state = rs.value
        return rs.value

    @property
    def tick(self):
        tick, t = ctypes.c_uint64(), ctypes.c_double()
        self._check(library().sdv_get_tick(self._h, ctypes.byref(tick), ctypes.byref(t)))
        return tick.value

    @property
    def time(self):
        tick, t = ctypes.c_uint64(), ctypes.c_double()
        self._check(library().sdv_get_tick(self._h, ctypes.byref(tick), ctypes.byref(t)))
        return t.value

    def events(self):
        """Events since the last call (collisions, maneuver changes, the end of the run)."""
        return self._array(library().sdv_poll_events, Event)

    def finish(self):
        """Ends the run now (expectations evaluated, outputs written); returns whether they held."""
        self._check(library().sdv_finish(self._h))
        passed = ctypes.c_int32()
        self._check(library().sdv_passed(self._h, ctypes.byref(passed)))
        return bool(passed.value)

    def close(self):
        if self._h is not None:
            library().sdv_destroy(self._h)
            self._h = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass
