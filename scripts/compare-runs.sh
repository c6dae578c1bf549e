#!/usr/bin/env bash
# Runs every example, NHTSA scenario, test scenario and GeoScenario scenario with two builds of
# `sdv` and compares their outputs byte for byte (trajectories.csv, summary.json, road.json,
# decisions.jsonl; with --gss-outputs also violations.json and trajectory_v*.csv): the check
# that a refactoring changed no behaviour. timing.json (wall clock) is not compared.
# Usage: scripts/compare-runs.sh OLD_SDV NEW_SDV
set -u
old=$1 new=$2
root=$(cd "$(dirname "$0")/.." && pwd)
gss=$root/../shared/data/geoscenario
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cases=() differ=0 n=0
for f in "$root"/examples/*.sdv "$root"/examples/nhtsa/*.sdv "$root"/tests/scenarios/data/*.sdv; do
    [ -f "$f" ] && cases+=("$f")
done
for f in "$gss"/scenarios/*.gs.osm; do
    [ -f "$f" ] && cases+=("$f")
done
for f in "${cases[@]}"; do
    name=$(basename "$f")
    extra=(--trace)
    case $f in *.gs.osm) extra+=(--btree-path "$gss/btrees/sdv" --gss-outputs) ;; esac
    for which in old new; do
        bin=$old; [ $which = new ] && bin=$new
        (cd "$root" && "$bin" run "$f" -o "$tmp/$which/$name" "${extra[@]}" > "$tmp/$which.$name.log" 2>&1)
        echo "exit $?" >> "$tmp/$which.$name.log"
    done
    n=$((n + 1))
    bad=""
    for out in "$tmp/old/$name"/*; do
        base=$(basename "$out")
        [ "$base" = timing.json ] && continue
        cmp -s "$out" "$tmp/new/$name/$base" || bad="$bad $base"
    done
    [ "$(ls "$tmp/old/$name" 2>/dev/null)" = "$(ls "$tmp/new/$name" 2>/dev/null)" ] || bad="$bad (file list)"
    grep -q "^exit" "$tmp/old.$name.log" && [ "$(tail -1 "$tmp/old.$name.log")" = "$(tail -1 "$tmp/new.$name.log")" ] || bad="$bad (exit code)"
    if [ -n "$bad" ]; then
        echo "DIFFERS $name:$bad"
        differ=$((differ + 1))
    else
        echo "same    $name"
    fi
done
echo "$((n - differ)) of $n scenarios byte-identical"
[ "$differ" -eq 0 ]
