#!/usr/bin/env bash
# Benchmark of `sdv view` on a large run (issue: 100 vehicles × 2 minutes must open in under
# 2 s): generates a 100-SDV scenario on a 4-lane road (bench/hundred.py), runs it for 120 s with
# a decision trace, writes the report and opens it RUNS times in headless Chromium through the
# browser test, which measures navigation → ready inside the page. Prints the report size and
# the load-time percentiles.  Usage: bench/view_load.sh [BUILD_DIR] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
runs=${2:-10}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 bench/hundred.py > "$tmp/hundred.sdv"
"$build/sdv" run "$tmp/hundred.sdv" -o "$tmp/run" --trace --view > /dev/null
size=$(stat -c %s "$tmp/run/report.html")
for i in $(seq "$runs"); do
    node tests/browser/browser_test.mjs "$tmp/run/report.html" "$tmp/shot.png" | sed -n 's/.*navigation→ready \([0-9]*\) ms.*/\1/p'
done | sort -n | python3 -c "
import sys
v = [int(x) for x in sys.stdin.read().split()]
p = lambda q: v[min(len(v) - 1, int(q * len(v)))]
print(f'report {$size / 1e6:.1f} MB; load (navigation to ready) over {len(v)} runs: p50 {p(0.5)} ms, p90 {p(0.9)} ms, max {v[-1]} ms')
"
