#!/usr/bin/env bash
# Co-simulation over real sockets with a Python stdlib client (proto3-JSON encoding), through the
# `sdv` executable: a whole session (then its replay), and every way a session can go wrong. Each
# case must end with the exit status documented in docs/cosim.md, and with the outputs written
# (summary.json marked aborted unless the client said Bye). Nothing here waits on the clock except
# through sdv's own time-out flags: the client waits for the port file only while sdv is alive,
# and sdv itself gives up after --cosim-connect-timeout; `timeout 600` only tells a hang from work.
#   cosim_robustness.sh SDV REPO_ROOT
set -u
sdv=$1
root=$2
scenario=$root/tests/cli/data/cosim_highway.sdv
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0

cat > "$dir/client.py" <<'PY'
# A minimal sdv-cosim v1 client speaking proto3-JSON; frames are a uint32 little-endian length
# and the JSON payload. (No 'encoding:' on the first two lines: Python reads that as a codec.)
import json, math, os, socket, struct, sys, time

mode, where, port_file, pid = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])

def alive():
    try:
        os.kill(pid, 0)
        return True
    except OSError:
        return False

while not os.path.exists(port_file):  # bounded by sdv's connect time-out: it exits then
    if not alive():
        sys.exit("client: sdv exited before it listened")
    time.sleep(0.02)
if where == "tcp":
    port = int(open(port_file).read())
    s = socket.create_connection(("127.0.0.1", port))
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
else:
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.connect(open(port_file).read().strip())
s.settimeout(300)

def send(msg):
    data = json.dumps(msg).encode()
    s.sendall(struct.pack("<I", len(data)) + data)

def recv_exact(n):
    buf = b""
    while len(buf) < n:
        chunk = s.recv(n - len(buf))
        if not chunk:
            return None
        buf += chunk
    return buf

def recv():
    head = recv_exact(4)
    if head is None:
        return None
    (n,) = struct.unpack("<I", head)
    return json.loads(recv_exact(n))

def expect_error(code):
    m = recv()
    if not m or "error" not in m or m["error"]["code"] != code:
        sys.exit(f"client: expected Error {code}, got {m}")
    print(f"client: got Error {code}: {m['error']['message']}")
    if recv() is not None:
        sys.exit("client: sdv did not close the connection after the Error")

def ego_next(obs):
    a = next(a for a in obs["actors"] if a["id"] == "1")
    a = dict(a)
    a["x"] += a["speed"] / 30 * math.cos(a["yaw"])
    a["y"] += a["speed"] / 30 * math.sin(a["yaw"])
    return a

def step(seq, obs, tick=None):
    t = obs["tick"] if tick is None else tick
    send({"seq": seq, "step": {"tick": t, "updates": [{"id": "1", "state": ego_next(obs)}]}})

if mode == "garbage":
    data = b"\x00\xffnot an envelope{"
    s.sendall(struct.pack("<I", len(data)) + data)
    expect_error("PROTOCOL_VIOLATION")
    sys.exit(0)
if mode == "huge":
    s.sendall(struct.pack("<I", 1 << 30) + b"x" * 100)
    expect_error("FRAME_TOO_LARGE")
    sys.exit(0)
if mode == "silent":
    expect_error("TIMEOUT")  # never says Hello: the connect time-out
    sys.exit(0)

send({"seq": 1, "hello": {"protocol": "sdv-cosim", "version_major": 1, "client_name": "robustness.py",
                          "claims": [{"actor_name": "ego", "mode": "CONTROL_MODE_POSE"}]}})
w = recv()
if not w or "welcome" not in w:
    sys.exit(f"client: expected Welcome, got {w}")
obs = w["welcome"]["initial"]
if mode == "stall":
    expect_error("TIMEOUT")
    sys.exit(0)
if mode == "bad_tick":
    step(2, obs, tick=5)
    expect_error("BAD_TICK")
    sys.exit(0)
if mode == "nan":
    st = ego_next(obs)
    st["speed"] = "NaN"
    send({"seq": 2, "step": {"tick": obs["tick"], "updates": [{"id": "1", "state": st}]}})
    expect_error("INVALID_VALUE")
    sys.exit(0)
seq = 2
while True:
    step(seq, obs)
    r = recv()
    if not r or "step_result" not in r:
        sys.exit(f"client: expected StepResult, got {r}")
    obs = r["step_result"]["observation"]
    seq += 1
    if mode == "disconnect" and seq == 12:
        s.sendall(struct.pack("<I", 500) + b'{"seq": 12, "st')  # half a frame, then gone
        s.close()
        print("client: disconnected in the middle of a frame at tick", obs["tick"])
        sys.exit(0)
    if r["step_result"]["run_state"] != "RUNNING":
        break
send({"seq": seq, "bye": {"reason": "done"}})
if recv() is not None:
    sys.exit("client: sdv did not close the connection after Bye")
print("client: Bye after tick", obs["tick"], r["step_result"]["run_state"])
PY

# case NAME EXPECTED_STATUS CLIENT_MODE ABORTED(true|false) TRANSPORT(tcp|unix) [sdv args...]
case_() {
    local name=$1 expected=$2 mode=$3 aborted=$4 transport=$5
    shift 5
    local d=$dir/$name
    mkdir -p "$d"
    local endpoint=tcp://127.0.0.1:0
    [ "$transport" = unix ] && endpoint=unix:$d/s.sock
    timeout 600 "$sdv" run "$scenario" --cosim "$endpoint" --cosim-port-file "$d/port" --cosim-encoding json \
        -o "$d/out" "$@" >"$d/stdout" 2>"$d/stderr" &
    local pid=$!
    local client_ok=0
    if [ "$mode" != none ]; then
        timeout 600 python3 "$dir/client.py" "$mode" "$transport" "$d/port" "$pid" >"$d/client" 2>&1 || client_ok=1
    fi
    # A client that failed may leave sdv waiting for it until a time-out: end it now.
    [ $client_ok = 0 ] || kill "$pid" 2>/dev/null
    wait "$pid"
    local code=$?
    local why=""
    [ "$code" = "$expected" ] || why="exit status $code (expected $expected)"
    [ $client_ok = 0 ] || why="$why; client failed: $(tail -1 "$d/client")"
    grep -q "^listening on " "$d/stdout" || why="$why; no 'listening on' line on stdout"
    if [ ! -f "$d/out/summary.json" ]; then
        why="$why; no summary.json"
    elif ! python3 -c "import json,sys; c=json.load(open(sys.argv[1]))['cosim']; sys.exit(c['aborted'] != (sys.argv[2] == 'true'))" \
            "$d/out/summary.json" "$aborted"; then
        why="$why; summary.json cosim.aborted is not $aborted"
    fi
    if [ -n "$why" ]; then
        echo "FAIL $name:$why"
        sed 's/^/    /' "$d/stderr" "$d/client" | head -20
        fail=1
    else
        echo "ok   $name: exit $code; $(grep -m1 -E 'error|Bye' "$d/stderr" "$d/stdout" | cut -d: -f2- | cut -c1-110)"
    fi
}

case_ session_tcp 0 full false tcp --cosim-record "$dir/session.cosim"
case_ session_unix 0 full false unix --cosim-step-timeout 120
case_ disconnect_mid_frame 4 disconnect true tcp
case_ stall_step_timeout 6 stall true tcp --cosim-step-timeout 2
case_ no_hello_connect_timeout 6 silent true tcp --cosim-connect-timeout 2
case_ no_client 6 none true tcp --cosim-connect-timeout 1
case_ garbage 5 garbage true tcp
case_ frame_1GiB 5 huge true unix
case_ bad_tick 5 bad_tick true tcp
case_ nan 5 nan true tcp

# The two transports and the replay of the record: the same trajectories, byte for byte.
for f in trajectories.csv summary.json; do
    if ! cmp -s "$dir/session_tcp/out/$f" "$dir/session_unix/out/$f"; then
        echo "FAIL tcp and unix sessions differ in $f"
        fail=1
    fi
done
if out=$(timeout 600 "$sdv" replay-cosim "$dir/session.cosim" -o "$dir/replay" 2>&1) &&
    grep -q "^replayed 120 steps of .*: all 121 replies identical" <<<"$out" &&
    cmp -s "$dir/session_tcp/out/trajectories.csv" "$dir/replay/trajectories.csv" &&
    cmp -s "$dir/session_tcp/out/summary.json" "$dir/replay/summary.json"; then
    echo "ok   replay-cosim: $(head -1 <<<"$out")"
else
    echo "FAIL replay-cosim:"
    sed 's/^/    /' <<<"$out" | head -10
    fail=1
fi
# An external vehicle without --cosim is a usage error that names the vehicle and the flag.
err=$("$sdv" run "$scenario" -o "$dir/plain" 2>&1 >/dev/null)
code=$?
if [ $code = 2 ] && grep -q "vehicle 'ego'.*--cosim" <<<"$err"; then
    echo "ok   external without --cosim: exit 2"
else
    echo "FAIL external without --cosim: exit $code: $err"
    fail=1
fi
[ $fail -eq 0 ] && echo "all co-simulation cases end as documented"
exit $fail
