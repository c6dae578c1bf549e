#!/usr/bin/env bash
# Runs are byte-identical: twice the same, --threads 1 vs 2 and 4, and .sdv vs its .sdvir.
set -u
sdv=$1
root=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
for ex in "$root"/examples/*.sdv "$root"/examples/pedestrians/*.sdv; do
    name=$(basename "$ex" .sdv)
    "$sdv" run "$ex" -o "$dir/$name.a" --threads 1 >/dev/null
    "$sdv" run "$ex" -o "$dir/$name.b" --threads 1 >/dev/null
    "$sdv" run "$ex" -o "$dir/$name.c" --threads 2 >/dev/null
    "$sdv" run "$ex" -o "$dir/$name.d" --threads 4 >/dev/null
    "$sdv" compile "$ex" -o "$dir/$name.sdvir" >/dev/null
    "$sdv" run "$dir/$name.sdvir" -o "$dir/$name.e" --threads 2 >/dev/null
    # A file with several scenarios writes one directory per scenario.
    files=$(cd "$dir/$name.a" && find . \( -name trajectories.csv -o -name summary.json -o -name road.json \) | sort)
    [ -n "$files" ] || { echo "FAIL $name: no outputs"; fail=1; }
    for run in b c d e; do
        for f in $files; do
            if ! cmp -s "$dir/$name.a/$f" "$dir/$name.$run/$f"; then
                echo "FAIL $name: $f differs between run a and run $run"
                fail=1
            fi
        done
    done
    [ $fail -eq 0 ] && echo "ok   $name: 5 runs byte-identical (threads 1, 2, 4; .sdv and .sdvir)"
done
# At scale (issue "scale"): 1,000 SDVs in two lanes around a blocked lane, 5 simulated seconds,
# byte-identical with 1, 2 and 4 threads (the grid, the shared reference lines and the parallel
# advance change nothing).
{
    echo 'import "std/drive.sdv"'
    echo 'import "std/lane_change.sdv"'
    echo 'road r { lanes 2 forward  speed_limit 60 km/h  straight 14000 m }'
    echo 'tree passer() { fallback { sequence { condition lane_occupied(lane = current, distance = 40 m)'
    echo '  condition vehicle_stopped(vehicle = front)  subtree std.lane_change(lane = left, gap = 15 m) }'
    echo '  subtree std.drive(speed = 12 m/s) } }'
    echo 'scenario big { road r  timeout 5 s'
    echo '  object block { start lane 1 at 12530 m }'
    for i in $(seq 0 999); do
        echo "  vehicle v$i: sdv { start lane $((i % 2 + 1)) at $((10 + 25 * (i / 2))) m speed 12 m/s tree passer() }"
    done
    echo '  expect no_collision() }'
} > "$dir/big.sdv"
for th in 1 2 4; do "$sdv" run "$dir/big.sdv" -o "$dir/big.$th" --threads $th >/dev/null; done
for th in 2 4; do
    for f in trajectories.csv summary.json; do
        if ! cmp -s "$dir/big.1/$f" "$dir/big.$th/$f"; then
            echo "FAIL big (1,000 SDVs): $f differs between --threads 1 and $th"
            fail=1
        fi
    done
done
rows=$(($(wc -l < "$dir/big.1/trajectories.csv") - 1))
[ "$rows" -eq $((1001 * 151)) ] || { echo "FAIL big: $rows trajectory rows, expected $((1001 * 151))"; fail=1; }
[ $fail -eq 0 ] && echo "ok   big: 1,000 SDVs byte-identical with threads 1, 2, 4"
# A different seed changes nothing in a scenario without random sampling, but is recorded.
"$sdv" run "$root/examples/cut_in.sdv" -o "$dir/seed" --seed 99 >/dev/null
grep -q '"seed": 99' "$dir/seed/summary.json" || { echo "FAIL: --seed not recorded"; fail=1; }
exit $fail
