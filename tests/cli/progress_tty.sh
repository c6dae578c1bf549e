#!/usr/bin/env bash
# `sdv run` shows its progress on a terminal only (issue 20): under a pseudo-terminal (script(1))
# stderr has the progress line (simulated time of the timeout, real-time factor) and each event as
# it happens; with stderr not a terminal there is no progress line and no carriage return.
# Usage: progress_tty.sh SDV ROOT
set -u
sdv=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
example=$root/examples/red_light.sdv
script -qec "'$sdv' run '$example' -o '$tmp/a'" /dev/null > "$tmp/tty.txt" 2>&1
grep -q "red_light: [0-9.]* / 45.0 s simulated, [0-9]*x real time" "$tmp/tty.txt" || { echo "FAIL: no progress line on a terminal"; fail=1; }
# The goal event shows as it happens: before the report's summary line.
live=$(grep -n "goal_reached car" "$tmp/tty.txt" | head -1 | cut -d: -f1)
summary=$(grep -n "s simulated in" "$tmp/tty.txt" | head -1 | cut -d: -f1)
if [ -z "$live" ] || [ -z "$summary" ] || [ "$live" -gt "$summary" ]; then
    echo "FAIL: the event is not shown as it happens (line ${live:-none}, summary line ${summary:-none})"
    fail=1
fi
"$sdv" run "$example" -o "$tmp/b" > "$tmp/out.txt" 2> "$tmp/err.txt"
if grep -q "real time" "$tmp/err.txt" || grep -q $'\r' "$tmp/err.txt" "$tmp/out.txt"; then
    echo "FAIL: progress output without a terminal"
    fail=1
fi
cmp -s "$tmp/a/trajectories.csv" "$tmp/b/trajectories.csv" || { echo "FAIL: the terminal run's outputs differ"; fail=1; }
[ $fail -eq 0 ] && echo "ok: progress on a terminal only"
exit $fail
