#!/usr/bin/env bash
# Benchmark of the sweep report (`sdv view SWEEP_DIR`) on large sweeps: the two 10,000-variant
# sweeps of the browser tests (grid2: a 50x50 heat map, four variants per cell; latin3: three
# continuous parameters, parallel coordinates and scatter), each opened RUNS times in headless
# Chromium through the browser test, which measures navigation → ready inside the page and the
# time to switch the outcome shown (every mark re-rendered). Prints the percentiles per sweep.
# The budgets (ready in 10 s, a switch in 5 s) are checked here, not in the browser test: no test
# depends on wall-clock speed.  Usage: bench/sweep_report_load.sh [BUILD_DIR] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
runs=${2:-10}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
for kind in grid2 latin3; do
    dir=$tmp/$kind
    node tests/browser/sweep_report_test.mjs --generate "$kind" 10000 "$dir" > /dev/null
    "$build/sdv" view "$dir" -o "$dir/report.html" > /dev/null
    size=$(stat -c %s "$dir/report.html")
    for i in $(seq "$runs"); do
        out=$(node tests/browser/sweep_report_test.mjs "$dir/report.html" "$tmp/shot.png") ||
            { echo "$out" | grep -v '^PASS' >&2; exit 1; }
        ready=$(echo "$out" | sed -n 's/.*navigation→ready \([0-9]*\) ms.*/\1/p')
        switches=$(echo "$out" | sed -n 's/.*outcome switches \([0-9, ]*\) ms.*/\1/p' | tr -d ' ')
        echo "$ready $switches"
    done | python3 -c "
import sys
ready, switch = [], []
for line in sys.stdin:
    r, s = line.split()
    ready.append(int(r))
    switch += [int(x) for x in s.split(',')]
def pct(v):
    v = sorted(v)
    p = lambda q: v[min(len(v) - 1, int(q * len(v)))]
    return f'p50 {p(0.5)} ms, p90 {p(0.9)} ms, max {v[-1]} ms'
print(f'$kind 10000: report {$size / 1e6:.2f} MB; ready over {len(ready)} opens: {pct(ready)}; '
      f'outcome switch over {len(switch)}: {pct(switch)}')
over = max(ready) > 10000 or max(switch) > 5000
print('  over budget (ready 10 s, switch 5 s)' if over else '  within budget (ready 10 s, switch 5 s)')
sys.exit(1 if over else 0)
" || status=1
done
exit $status
