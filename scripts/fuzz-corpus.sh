#!/usr/bin/env bash
# Gathers the seed corpus of every fuzz target (tests/fuzz/README.md) from the real inputs:
#   scripts/fuzz-corpus.sh BUILD_DIR OUT_DIR
# OUT_DIR/<target>/ gets the committed corpus (tests/fuzz/corpus) and reproducers
# (tests/fuzz/regressions), the examples, the standard
# library, the golden inputs, the third-party data of ../shared/data (GeoScenario trees and
# scenarios, Lanelet2 maps and small maps cut from them), the deep and long seeds of
# tests/fuzz/gen_deep.py and, when BUILD_DIR holds a built `sdv`, what it makes: the IR of every
# example, recorded co-simulation sessions in both encodings, a sweep directory and the rows of a
# sweep. Each seed is named after where it came from. OUT_DIR is replaced.
set -euo pipefail
shopt -s globstar nullglob
if [ $# -ne 2 ]; then
    echo "usage: $0 BUILD_DIR OUT_DIR" >&2
    exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$1" && pwd)
out=$2
shared=$root/../shared/data
targets=(sdv_frontend ir_reader btree gss_scenario lanelet2 cosim_frame sweep_results recording run_dir run_diff
         sweep_rows)
rm -rf "$out"
for t in "${targets[@]}"; do mkdir -p "$out/$t"; done
out=$(cd "$out" && pwd)

# seed_name FILE: its path relative to the repository (or "shared_" + relative to ../shared), as
# one file name.
seed_name() {
    local p
    p=$(realpath -m "$1")
    case $p in
        "$root"/*) p=${p#"$root"/} ;;
        *) p=shared_$(realpath -m --relative-to="$root/../shared" "$p") ;;
    esac
    echo "${p//\//_}"
}

# add TARGET FILE...: copies each file under a name made of its path (relative to the repository
# or to ../shared/data), so that seeds from different places never collide.
add() {
    local t=$1 f name
    shift
    for f in "$@"; do
        [ -f "$f" ] || continue
        name=$(seed_name "$f")
        cp "$f" "$out/$t/$name"
    done
}

for t in "${targets[@]}"; do
    for f in "$root/tests/fuzz/corpus/$t/"*; do cp "$f" "$out/$t/"; done
    add "$t" "$root/tests/fuzz/regressions/$t/"*
done
add sdv_frontend "$root"/examples/**/*.sdv "$root"/stdlib-trees/*.sdv "$root"/tests/golden/**/input.sdv \
    "$root"/tests/*/data/*.sdv
add ir_reader "$root"/tests/golden/**/*.sdvir
add btree "$root"/tests/golden/**/input.btree "$shared"/geoscenario/btrees/**/*.btree
add gss_scenario "$root"/tests/golden/**/input.osm "$root"/tests/scenarios/data/*.osm "$shared"/geoscenario/scenarios/**/*.osm
add lanelet2 "$shared"/lanelet2/*.osm "$shared"/geoscenario/maps/*.osm
add recording "$shared"/recorded/commonroad/*.xml "$root"/tests/cli/data/realism/*.csv
# Small maps cut from the big ones: the fuzzer mutates them thousands of times faster.
for map in "$shared"/lanelet2/mapping_example.osm "$shared"/geoscenario/maps/lanelet2_university_weber_alt.osm \
           "$shared"/geoscenario/maps/ll2_firetower_4waystop.osm "$shared"/geoscenario/maps/lanelet2_ringroad.osm; do
    [ -f "$map" ] && python3 "$root/tests/fuzz/seed_tools.py" crop-lanelet2 "$map" 6 "$out/lanelet2"
done
python3 "$root/tests/fuzz/seed_tools.py" cosim-frames "$out/cosim_frame"
python3 "$root/tests/fuzz/gen_deep.py" "$out"

sdv=$build/sdv
if [ ! -x "$sdv" ]; then
    echo "fuzz-corpus: no $sdv: no compiled IR, co-simulation records, sweeps or traced runs (seeds of" \
         "ir_reader, cosim_frame, sweep_results, sweep_rows, run_dir and run_diff)" >&2
else
    # The sanitizers of an instrumented sdv must not stop it on a leak at exit.
    export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    for f in "$root"/examples/**/*.sdv "$root"/tests/fuzz/corpus/sdv_frontend/*.sdv; do
        "$sdv" compile "$f" -o "$out/ir_reader/$(seed_name "$f")ir" >/dev/null 2>&1 || true
    done
    # Co-simulation sessions of the scenario the target embeds, driven by the reference client
    # (python3-protobuf for the binary encoding: Debian's python3 has it).
    py=python3
    /usr/bin/python3 -c "import google.protobuf" 2>/dev/null && py=/usr/bin/python3
    for enc in json binary; do
        d=$tmp/cosim_$enc
        mkdir -p "$d"
        timeout 300 "$sdv" run "$root/tests/cli/data/cosim_highway.sdv" --cosim tcp://127.0.0.1:0 \
            --cosim-port-file "$d/port" --cosim-encoding $enc --cosim-record "$d/session.cosim" \
            --cosim-connect-timeout 60 -o "$d/out" >"$d/sdv.log" 2>&1 &
        pid=$!
        timeout 300 "$py" "$root/examples/cosim/ads_client.py" --port-file "$d/port" --encoding $enc \
            >"$d/client.log" 2>&1 || echo "fuzz-corpus: the $enc co-simulation client failed (see no $enc records)" >&2
        wait $pid || true
        if [ -s "$d/session.cosim" ]; then
            for n in 4 16 40; do
                python3 "$root/tests/fuzz/seed_tools.py" truncate-record "$d/session.cosim" $n "$out/cosim_frame/record_${enc}_$n"
            done
            python3 "$root/tests/fuzz/seed_tools.py" record-to-wire "$out/cosim_frame/record_${enc}_40" "$out/cosim_frame/wire_${enc}_40"
        fi
    done
    # A sweep of the paper's cut-in table (15 variants).
    "$sdv" sweep "$root/examples/sweeps/cut_in_table.sdv" -o "$tmp/sweep" >"$tmp/sweep.log" 2>&1 || true
    if [ -f "$tmp/sweep/results.csv" ]; then
        python3 "$root/tests/fuzz/seed_tools.py" sweep-seed "$tmp/sweep" "$out/sweep_results/cut_in_table_sweep"
    else
        echo "fuzz-corpus: the sweep of examples/sweeps/cut_in_table.sdv wrote no results.csv:" >&2
        tail -3 "$tmp/sweep.log" >&2
    fi
    # The rows of the sweep_rows target's own campaign, as this sdv writes them.
    "$sdv" sweep "$root/tests/fuzz/targets/sweep_rows.sdv" -o "$tmp/rows" >"$tmp/rows.log" 2>&1 || true
    if [ -f "$tmp/rows/rows/slice-0-of-1.csv" ]; then
        cp "$tmp/rows/rows/slice-0-of-1.csv" "$out/sweep_rows/sweep_rows_sweep.csv"
    else
        echo "fuzz-corpus: the sweep of tests/fuzz/targets/sweep_rows.sdv wrote no rows:" >&2
        tail -3 "$tmp/rows.log" >&2
    fi
    # Run directories (sdv view, sdv plot): a traced cut-in, pedestrians at a crossing with
    # walkways and crosswalks in road.json, and a replay of recorded traffic (recorded.csv);
    # their first second, so that the seeds stay small.
    "$sdv" run "$root/examples/cut_in.sdv" --trace -o "$tmp/run_cut_in" >/dev/null 2>&1 || true
    "$sdv" run "$root/examples/pedestrians/cpna.sdv" --trace -o "$tmp/run_cpna" >/dev/null 2>&1 || true
    "$sdv" replay "$shared/recorded/commonroad/USA_Peach-4_8_T-1.xml" --sdv all -o "$tmp/replay" >/dev/null 2>&1 || true
    pedestrians=("$tmp"/run_cpna/*)  # one directory per scenario of the file
    replays=("$tmp"/replay/runs/v*)
    for d in "$tmp/run_cut_in" "${pedestrians[@]:0:1}" "${replays[@]:0:2}"; do
        [ -f "$d/trajectories.csv" ] || continue
        python3 "$root/tests/fuzz/seed_tools.py" run-seed "$d" 30 "$out/run_dir/$(basename "$d")_1s"
    done
    compgen -G "$out/run_dir/*_1s" >/dev/null || echo "fuzz-corpus: no run directory seeds (sdv run and replay failed)" >&2
    # Pairs of run directories (sdv diff --runs): the traced cut-in against itself and against
    # the same scenario with the cutting-in driver 1 m/s faster (they part at tick 21); 2 s each.
    sed 's/tree cut_in_driver(speed = 18 m\/s)/tree cut_in_driver(speed = 19 m\/s)/' "$root/examples/cut_in.sdv" >"$tmp/cut_in_faster.sdv"
    "$sdv" run "$tmp/cut_in_faster.sdv" --trace -o "$tmp/run_cut_in_faster" >/dev/null 2>&1 || true
    if [ -f "$tmp/run_cut_in/trajectories.csv" ] && [ -f "$tmp/run_cut_in_faster/trajectories.csv" ]; then
        python3 "$root/tests/fuzz/seed_tools.py" diff-seed "$tmp/run_cut_in" "$tmp/run_cut_in" 60 "$out/run_diff/cut_in_itself_2s"
        python3 "$root/tests/fuzz/seed_tools.py" diff-seed "$tmp/run_cut_in" "$tmp/run_cut_in_faster" 60 "$out/run_diff/cut_in_faster_2s"
    else
        echo "fuzz-corpus: no run diff seeds (sdv run failed)" >&2
    fi
fi
for t in "${targets[@]}"; do
    printf '%-14s %5d seeds, %8d bytes\n' "$t" "$(find "$out/$t" -type f | wc -l)" "$(cat "$out/$t"/* | wc -c)"
done
