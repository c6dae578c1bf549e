#!/usr/bin/env bash
# Runs one libFuzzer target of tests/fuzz (tests/fuzz/README.md) and records the run in
# docs/reliability.md.
#
#   scripts/fuzz.sh TARGET [MINUTES] [--no-sanitizers] [--runs N [--resume] | --ci] [--keep-going]
#                   [--record|--no-record] [--corpus DIR] [--jobs N] [--no-build]
#
# TARGET is a name of tests/fuzz/targets (sdv_frontend ir_reader btree gss_scenario lanelet2
# cosim_frame sweep_results recording run_dir run_diff sweep_rows). The run is bounded by time
# (MINUTES, default 10) or, with --runs N, by the number of inputs executed (the seeds
# included); --ci is --runs with the target's CI count (below) and --no-build, as
# scripts/check.sh runs it. It builds
# the fuzz preset (ASan+UBSan) or, with --no-sanitizers, fuzz-nosan, then gathers the seed corpus
# once into build/<preset>/corpus (scripts/fuzz-corpus.sh; --corpus DIR uses another). New inputs
# go to build/<preset>/fuzz-work/TARGET, kept between runs; findings to
# build/<preset>/findings/TARGET/ (crash-*, timeout-*, oom-*, leak-*: replay one with
# `build/<preset>/fuzz/fuzz_TARGET FILE`, then add it to tests/fuzz/regressions/TARGET/).
# Every input that takes more than 1 s is a finding (-timeout=1; 3 s for sdv_frontend under
# ASan+UBSan, below), as is one using more than 2 GB. The run stops at the first finding unless
# --keep-going (libFuzzer's fork mode: each finding is saved and counted, the fuzzing goes on).
# A time-bounded run rewrites its row (target and build) of the table in docs/reliability.md
# unless --no-record; a count-bounded one only with --record.
# --resume makes a count-bounded run a campaign in parts (10 million executions take hours, more
# than one sitting): the first part copies the executable and keeps it, with its corpus and the
# executions so far, in build/<preset>/campaigns/TARGET; stop a part at any time (SIGTERM to the
# fuzzer's main process, pkill -o) and run the same command again to go on with the same
# executable from that corpus, until N executions in all. The row is recorded when the campaign ends, its executions summed
# over the parts, the commit its executable was built from in its bound.
# Exit status: 0 no finding, 1 a finding, 2 usage or build errors.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
targets=(sdv_frontend ir_reader btree gss_scenario lanelet2 cosim_frame sweep_results recording run_dir run_diff
         sweep_rows)

# The largest input of each target (-max_len): above its biggest real input and the deep seeds
# of tests/fuzz/gen_deep.py (Lanelet2 maps of ../shared/data reach 730 KB). The three front ends
# that parse with ANTLR (.sdv, .btree, .gs.osm) read at most 64 KB, the largest input the known
# findings of the .sdv and .btree front ends needed (issue 22: 30-64 KB; the quadratic names of
# .gs.osm finding 23 passed 1 s from 49 KB): their work is linear, but dense text (thousands of
# arguments in one call, of entries in one btconfig) costs the targets 7-10 µs a byte at -O2 and
# 20-35 under ASan+UBSan, so 256 KB of it passed 1 s in every build (docs/reliability.md).
# A run directory's readers (run_dir; run_diff, two of them) make one pass over each file; real
# ones are megabytes of the same rows, and 256 KB holds every kind of row and the deep seeds:
# larger inputs only slow it down. sweep_rows reads each line three ways, 25-40 µs a line under
# ASan+UBSan (11 exec/s at 256 KB, 214 at 8 KB): 8 KB hold every variant of its campaign ten times.
declare -A max_len=([sdv_frontend]=65536 [ir_reader]=262144 [btree]=65536 [gss_scenario]=65536
                    [lanelet2]=1048576 [cosim_frame]=262144 [sweep_results]=262144 [recording]=1048576
                    [run_dir]=262144 [run_diff]=262144 [sweep_rows]=8192)
# The time an input may take (-timeout, seconds) is 1 s, and under ASan+UBSan 3 s for those
# three: 64 KB of dense text cost up to 2.2 s there, two to four times its cost without
# sanitizers, where they keep the 1 s limit.
declare -A timeout_sanitized=([sdv_frontend]=3 [btree]=3 [gss_scenario]=3)
# The executions of a CI run (--ci), seeds included: about 20 s each under ASan+UBSan on one
# core of the development machine (docs/reliability.md has each target's exec/s).
declare -A ci_runs=([sdv_frontend]=2500 [ir_reader]=15000 [btree]=8000 [gss_scenario]=9000
                    [lanelet2]=7000 [cosim_frame]=3000 [sweep_results]=15000 [recording]=3000
                    [run_dir]=10000 [run_diff]=3000 [sweep_rows]=4000)

usage() {
    sed -n '4,8p' "$0" >&2
    exit 2
}

target="" minutes=10 preset=fuzz runs="" record="" corpus="" jobs=1 keep_going=0 ci=0 build_it=1 resume=0
while [ $# -gt 0 ]; do
    case $1 in
        --no-sanitizers) preset=fuzz-nosan ;;
        --runs) runs=${2:?}; shift ;;
        --record) record=1 ;;
        --keep-going) keep_going=1 ;;
        --resume) resume=1 ;;
        --ci) ci=1; build_it=0 ;;
        --no-build) build_it=0 ;;
        --no-record) record=0 ;;
        --corpus) corpus=${2:?}; shift ;;
        --jobs) jobs=${2:?}; shift ;;
        -h|--help) usage ;;
        -*) echo "fuzz.sh: unknown option $1" >&2; usage ;;
        *)
            if [ -z "$target" ]; then target=$1; else minutes=$1; fi ;;
    esac
    shift
done
[ -n "$target" ] || usage
if [ -z "${max_len[$target]:-}" ]; then
    echo "fuzz.sh: unknown target '$target' (targets: ${targets[*]})" >&2
    exit 2
fi
[ "$ci" = 0 ] || runs=${ci_runs[$target]}
if [ "$resume" = 1 ] && { [ -z "$runs" ] || [ "$ci" = 1 ]; }; then
    echo "fuzz.sh: --resume goes with --runs N" >&2
    usage
fi
[ -n "$record" ] || { [ -n "$runs" ] && record=0 || record=1; }

build=$root/build/$preset
cd "$root"
if [ "$build_it" = 1 ]; then
    if [ ! -f "$build/CMakeCache.txt" ]; then
        cmake --preset "$preset" >/dev/null || exit 2
    fi
    cmake --build "$build" --target "fuzz_$target" -j "$(nproc)" >"$build/fuzz-build-$target.log" 2>&1 || {
        tail -30 "$build/fuzz-build-$target.log" >&2
        echo "fuzz.sh: building fuzz_$target failed (log: $build/fuzz-build-$target.log)" >&2
        exit 2
    }
fi
exe=$build/fuzz/fuzz_$target
campaign=$build/campaigns/$target
# The state of a campaign in parts (--resume): its bound, the executions, seconds and findings of
# the parts so far, and the commit its executable was built from.
c_runs=0 c_execs=0 c_seconds=0 c_findings=0 c_parts=0 c_commit=""
if [ "$resume" = 1 ] && [ -f "$campaign/state" ]; then
    # shellcheck disable=SC1091
    . "$campaign/state"
    if [ "$c_runs" != "$runs" ]; then
        echo "fuzz.sh: $campaign is a campaign of $c_runs runs, not $runs: finish it, or delete the directory" >&2
        exit 2
    fi
    exe=$campaign/fuzz_$target
    echo "fuzz.sh: resuming $campaign: part $((c_parts + 1)), $c_execs of $c_runs executions done" >&2
fi
if [ ! -x "$exe" ]; then
    echo "fuzz.sh: no $exe: build the $preset preset first" >&2
    exit 2
fi
if [ "$resume" = 1 ] && [ ! -f "$campaign/state" ]; then
    rm -rf "$campaign" && mkdir -p "$campaign/work"
    cp -p "$exe" "$campaign/fuzz_$target"
    exe=$campaign/fuzz_$target
    c_runs=$runs
    # The commit the executable was built from: the last one before it was linked, with
    # "uncommitted changes" when files that differ from that commit are older than it.
    built=$(stat -c %Y "$exe")
    c_commit=$(git -C "$root" log -1 --format=%h --until="@$built")
    while IFS= read -r f; do
        if [ -f "$root/$f" ] && [ "$(stat -c %Y "$root/$f")" -le "$built" ]; then
            c_commit="$c_commit with uncommitted changes"
            break
        fi
    done < <(git -C "$root" diff --name-only "$c_commit")
fi

# The seed corpus: gathered once (delete the directory to gather again). The inputs are
# compiled, recorded and swept by the first `sdv` found (an uninstrumented one is faster).
if [ -z "$corpus" ]; then
    corpus=$build/corpus
    if [ ! -d "$corpus/$target" ]; then
        sdv_dir=""
        for d in build/ci build/release build/dev build/fuzz; do
            if [ -x "$d/sdv" ]; then sdv_dir=$d; break; fi
        done
        if [ -z "$sdv_dir" ]; then
            cmake --build "$build" --target sdv -j "$(nproc)" >>"$build/fuzz-build-$target.log" 2>&1 && sdv_dir=$build
        fi
        scripts/fuzz-corpus.sh "${sdv_dir:-$build}" "$corpus" >&2
    fi
fi
# The fuzzer runs in a scratch directory: every path it is given must be absolute.
corpus=$(realpath -m "$corpus")

work=$build/fuzz-work/$target
[ "$resume" = 0 ] || work=$campaign/work
findings=$build/findings/$target
mkdir -p "$work" "$findings"
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
save_state() {
    printf 'c_runs=%s\nc_execs=%s\nc_seconds=%s\nc_findings=%s\nc_parts=%s\nc_commit=%q\n' \
        "$c_runs" "$c_execs" "$c_seconds" "$c_findings" "$c_parts" "$c_commit" >"$campaign/state"
}
if [ "$resume" = 1 ]; then
    # Saved before the part too: a part cut short without its statistics (the machine stopped)
    # adds nothing, and the next goes on from its corpus.
    save_state
    # A part of a campaign goes on from the corpus of the parts before (another seed each).
    bound=(-runs="$((runs - c_execs))" -seed="$((c_parts + 1))")
elif [ -n "$runs" ]; then
    # A bounded run starts from the seeds alone, so that it is the same run every time.
    rm -rf "$work" && mkdir -p "$work"
    bound=(-runs="$runs" -seed=1)
else
    bound=(-max_total_time=$((minutes * 60)))
fi
# An input over 1 s is a finding of a long run (docs/reliability.md); CI only fails on a hang
# (60 s): its verdict must not depend on how busy the machine is.
per_input=1
[ "$preset" != fuzz ] || per_input=${timeout_sanitized[$target]:-1}
[ "$ci" = 0 ] || per_input=60
args=("${bound[@]}" -max_len="${max_len[$target]}" -timeout="$per_input" -rss_limit_mb=2048
      -dict="$root/tests/fuzz/dict/$target.dict" -artifact_prefix="$findings/" -print_final_stats=1
      -interrupted_exitcode=72)
# One process by default (as -jobs=1 -workers=1); --jobs N runs N jobs side by side, each in a
# child process writing fuzz-<k>.log in the working directory; --keep-going runs --jobs
# children at a time in fork mode.
if [ "$keep_going" = 1 ]; then
    args+=(-fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
elif [ "$jobs" -gt 1 ]; then
    args+=(-jobs="$jobs" -workers="$jobs")
fi
touch "$logs/start"
before=$(find "$findings" -type f | wc -l)
echo "fuzz.sh: fuzz_$target ($preset) ${bound[0]} over $corpus/$target" >&2
status=0
started=$SECONDS
(cd "$logs" && UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$exe" "${args[@]}" "$work" "$corpus/$target" >"$logs/main.log" 2>&1) || status=$?
seconds=$((SECONDS - started))
cat "$logs"/fuzz-*.log >"$logs/all.log" 2>/dev/null || true
cat "$logs/main.log" >>"$logs/all.log"
after=$(find "$findings" -type f | wc -l)
crashes=$((after - before))

# The numbers of the run: libFuzzer's final stats (summed over jobs) and the coverage of its
# last status line; in fork mode its last "#N: cov: ... time: Ts" line.
read -r execs rate cov ft < <(awk '
    /stat::number_of_executed_units:/ { execs += $2 }
    /stat::average_exec_per_sec:/ { rate += $2 }
    /^#[0-9]+:?[[:space:]].*cov: [0-9]+ ft: [0-9]+/ {
        for (i = 1; i < NF; i++) { if ($i == "cov:") c = $(i + 1); if ($i == "ft:") f = $(i + 1); if ($i == "time:") t = $(i + 1) }
        if (c + 0 > cov) cov = c + 0; if (f + 0 > ft) ft = f + 0
        if ($1 ~ /:$/) { n = substr($1, 2) + 0; if (n > fork_execs) fork_execs = n; sub(/s$/, "", t); fork_time = t + 0 } }
    END { if (execs == 0 && fork_execs > 0) { execs = fork_execs; rate = fork_time > 0 ? fork_execs / fork_time : 0 }
          printf "%d %d %d %d\n", execs, rate, cov, ft }' "$logs/all.log")
grep -E "^(INFO: (seed|.*files found)|#[0-9]+[[:space:]]+(INITED|DONE)|stat::|==[0-9]+==ERROR|SUMMARY|ALARM|sdv fuzz:)" \
    "$logs/all.log" | head -40 >&2 || true
# Exit status 72 without an artifact: stopped by SIGINT or SIGTERM, not a finding.
stopped=0
if [ "$status" -eq 72 ] && [ "$crashes" -eq 0 ]; then
    stopped=1 status=0
    echo "fuzz.sh: fuzz_$target stopped by a signal" >&2
fi
if [ "$keep_going" = 1 ] && [ "$crashes" -gt 0 ]; then
    echo "fuzz.sh: $crashes FINDING(s) in fuzz_$target:" >&2
    find "$findings" -type f -newer "$logs/start" | sed 's/^/    /' >&2
elif [ "$status" -ne 0 ] || [ "$crashes" -gt 0 ]; then
    echo "fuzz.sh: FINDING in fuzz_$target: exit status $status; artifacts:" >&2
    find "$findings" -type f -newer "$logs/start" | sed 's/^/    /' >&2
    grep -E -m5 "ERROR|runtime error|sdv fuzz:|ALARM" "$logs/all.log" | sed 's/^/    /' >&2 || true
    [ "$crashes" -gt 0 ] || crashes=1
fi
# A timeout is measured in wall-clock time: on a machine busy with other work an input of 0.4 s
# can pass 1 s. Each new timeout artifact is replayed three times in one process and the fastest
# of the last two (the first pays the target's one-time set-up) is printed next to the limit,
# so that a load artifact is told from a slow input. It stays counted as a finding.
for f in $(find "$findings" -type f -name 'timeout-*' -newer "$logs/start" 2>/dev/null); do
    ms=$("$exe" "$f" "$f" "$f" 2>&1 |
         awk '/^Executed .* in [0-9]+ ms/ { n++; if (n > 1 && (best == "" || $(NF - 1) + 0 < best)) best = $(NF - 1) + 0 }
              END { print best == "" ? "?" : best }') || ms="?"
    echo "fuzz.sh: $(basename "$f") replays alone in $ms ms (limit ${per_input} s)" >&2
done
echo "fuzz.sh: fuzz_$target: $execs executions, $rate exec/s, cov $cov ft $ft, $crashes finding(s)" >&2

if [ "$resume" = 1 ]; then
    c_parts=$((c_parts + 1)) c_execs=$((c_execs + execs)) c_seconds=$((c_seconds + seconds))
    c_findings=$((c_findings + crashes))
    save_state
    if [ "$c_execs" -lt "$c_runs" ]; then
        echo "fuzz.sh: campaign of fuzz_$target: $c_execs of $c_runs executions in $c_parts part(s)," \
             "$c_findings finding(s); run the same command to go on" >&2
        record=0
    else
        echo "fuzz.sh: campaign of fuzz_$target done: $c_execs executions in $c_parts part(s)," \
             "$c_findings finding(s)" >&2
        execs=$c_execs crashes=$c_findings
        rate=$((c_seconds > 0 ? c_execs / c_seconds : 0))
        mv "$campaign" "$campaign.done-$(date -u +%Y%m%d%H%M%S)"
    fi
fi

if [ "$record" = 1 ]; then
    doc=$root/docs/reliability.md
    build_kind=$([ "$preset" = fuzz ] && echo "ASan+UBSan" || echo "no sanitizers")
    bound_text=${runs:+"$runs runs"}
    bound_text=${bound_text:-"$minutes min"}
    parts_text=$([ "$c_parts" = 1 ] && echo "one part" || echo "$c_parts parts")
    [ "$resume" = 0 ] || bound_text="$bound_text in $parts_text (one executable, built from $c_commit)"
    [ "$keep_going" = 0 ] || bound_text="$bound_text, fork mode"
    [ "$per_input" = 1 ] || bound_text="$bound_text, ${per_input} s per input"
    [ "$stopped" = 0 ] || [ "$resume" = 1 ] || bound_text="$bound_text, stopped by a signal"
    date=$(date -u +%Y-%m-%d)
    row="| $target | $build_kind | $execs | $rate | $cov | $ft | $crashes | $bound_text | $date |"
    python3 - "$doc" "$target" "$build_kind" "$row" <<'PY'
import pathlib, sys
doc, target, build, row = pathlib.Path(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
begin, end = "<!-- fuzz-runs:begin -->", "<!-- fuzz-runs:end -->"
header = ["| target | build | executions | exec/s | coverage (edges) | features | findings | bound | date |",
          "|---|---|---:|---:|---:|---:|---:|---|---|"]
text = doc.read_text(encoding="utf-8") if doc.exists() else "# Reliability\n\n" + begin + "\n" + end + "\n"
if begin not in text:
    text += "\n" + begin + "\n" + end + "\n"
head, rest = text.split(begin, 1)
table, tail = rest.split(end, 1)
rows = [l for l in table.strip().splitlines() if l.startswith("| ") and not l.startswith("| target ")]
key = lambda l: [c.strip() for c in l.strip("|").split("|")][:2]
rows = [l for l in rows if key(l) != [target, build]] + [row]
rows.sort(key=key)
doc.write_text(head + begin + "\n" + "\n".join(header + rows) + "\n" + end + tail, encoding="utf-8")
PY
    echo "fuzz.sh: recorded in docs/reliability.md" >&2
fi
[ "$status" -eq 0 ] && [ "$crashes" -eq 0 ]
