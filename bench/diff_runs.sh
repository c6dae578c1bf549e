#!/usr/bin/env bash
# Benchmark of `sdv diff --runs` on large runs: two run directories of AGENTS agents for TICKS
# ticks each (default 300 x 3,600: 1,080,000 rows, 92 MB of trajectories.csv), equal, so that
# every row is read, sorted and compared. Prints the wall time percentiles and the peak memory.
# Usage: bench/diff_runs.sh [BUILD_DIR] [RUNS] [AGENTS] [TICKS]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
runs=${2:-5}
agents=${3:-300}
ticks=${4:-3600}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/a" "$tmp/b"
python3 - "$tmp/a/trajectories.csv" "$agents" "$ticks" <<'PY'
import sys
path, agents, ticks = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
with open(path, "w") as out:
    out.write("time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver\n")
    for t in range(ticks):
        out.write("".join(f"{t / 30:.4f},{t},v{v},sdv,{t * 0.5 + v * 10:.4f},0.0000,0.0000,15.0000,0.0000,{t * 0.5:.4f},"
                          f"0.0000,a.1,keep\n" for v in range(agents)))
PY
cp "$tmp/a/trajectories.csv" "$tmp/b/"
echo "rows: $((agents * ticks)), trajectories.csv: $(($(stat -c %s "$tmp/a/trajectories.csv") / 1000000)) MB each"
for i in $(seq "$runs"); do
    /usr/bin/time -f "%e %M" -o "$tmp/time" "$build/sdv" diff --runs "$tmp/a" "$tmp/b" > /dev/null
    cat "$tmp/time"
done | python3 -c "
import sys
rows = [line.split() for line in sys.stdin.read().splitlines()]
secs = sorted(float(r[0]) for r in rows)
kb = max(int(r[1]) for r in rows)
pick = lambda q: secs[min(len(secs) - 1, int(q * len(secs)))]
print(f'sdv diff --runs: p50 {pick(0.5):.2f} s, p90 {pick(0.9):.2f} s, max {secs[-1]:.2f} s over {len(secs)} runs; peak memory {kb // 1024} MB')
"
