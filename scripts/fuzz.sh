#!/usr/bin/env bash
# Runs one libFuzzer target of tests/fuzz (tests/fuzz/README.md) and records the run in
# docs/reliability.md.
#
#   scripts/fuzz.sh TARGET [MINUTES] [--no-sanitizers] [--runs N [--resume [--parts P]
#                   [--part-minutes M] [--part-runs K] [--state-dir DIR]] | --ci] [--keep-going]
#                   [--record|--no-record] [--corpus DIR] [--jobs N] [--no-build] [--build-dir DIR]
#   scripts/fuzz.sh TARGET [--no-sanitizers] [--state-dir DIR] [--build-dir DIR] --stop
#
# TARGET is a name of tests/fuzz/targets (sdv_frontend ir_reader btree gss_scenario lanelet2
# cosim_frame sweep_results recording run_dir run_diff sweep_rows). The run is bounded by time
# (MINUTES, default 10) or, with --runs N, by the number of inputs executed (the seeds
# included); --ci is --runs with the target's CI count (below) and --no-build, as
# scripts/check.sh runs it. It builds
# the fuzz preset (ASan+UBSan) or, with --no-sanitizers, fuzz-nosan, then gathers the seed corpus
# once into build/<preset>/corpus (scripts/fuzz-corpus.sh; --corpus DIR uses another; --build-dir
# DIR builds and runs the preset's executables in DIR instead of build/<preset>). New inputs
# go to build/<preset>/fuzz-work/TARGET, kept between runs; findings to
# build/<preset>/findings/TARGET/ (crash-*, timeout-*, oom-*, leak-*: replay one with
# `build/<preset>/fuzz/fuzz_TARGET FILE`, then add it to tests/fuzz/regressions/TARGET/).
# Every input that takes more than 1 s is a finding (-timeout=1; 3 s for the ANTLR front ends
# and lanelet2 under ASan+UBSan, below), as is one using more than 2 GB. The run stops at the
# first finding unless --keep-going (libFuzzer's fork mode: each finding is saved and counted, the
# fuzzing goes on).
# A time-bounded run rewrites its row (target and build) of the table in docs/reliability.md
# unless --no-record; a count-bounded one only with --record.
#
# --resume makes a count-bounded run a campaign: N executions of one executable, in parts that
# may span days and machines (tests/fuzz/README.md). Its state is committed:
# tests/fuzz/campaigns/PRESET/TARGET (--state-dir DIR: DIR/PRESET/TARGET) holds the bound, the
# executions, seconds, findings and parts so far, the commit the executable was built from and
# its SHA-256; the artifacts of its findings are copied beside it (TARGET.findings/); with
# --state-dir, this machine's copy of the campaign is in DIR/machine, not in build/. The
# command runs parts of M minutes (--part-minutes, default 30; --part-runs K: at most K
# executions a part) one after the other until N executions in all, or P parts (--parts), or a
# signal (SIGTERM or SIGINT to this script or to the fuzzer's main process; --stop sends it to the
# script of the campaign of TARGET running on this machine and waits until the part under way is
# counted); the state is written after every part, so a machine that stops loses one part at most.
# Run the same command again to go on. On a machine without the campaign's copy of its
# executable (build/PRESET/campaigns/TARGET) the executable is found again by its SHA-256: the
# current build's if it is the same bytes (without sanitizers a build does not depend on its
# directory), else a build of the commit's source (git archive into build/campaign-src/COMMIT,
# built as the campaign's source directory in a private mount namespace); other bytes are refused.
# The row is recorded when the campaign ends, with --record also a row a part in the table of
# campaigns under way.
# Exit status: 0 no finding, 1 a finding, 2 usage or build errors.
# The whole script is one block, read before it runs: a campaign runs for hours, and bash reads a
# script as it goes, so an edit of this file would otherwise change the commands of a run under way.
{
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
# sanitizers, where they keep the 1 s limit. Also 3 s for lanelet2 under ASan+UBSan: a map at its
# limit (100 km of lanes, which 3 KB of stacked lanelets declare) costs the target 1.0-1.3 s there
# (every reference line sampled every 0.25 m and probed for the Frenet round trip; about 0.2 s at
# -O2): finding 21's committed reproducer passed 1 s.
declare -A timeout_sanitized=([sdv_frontend]=3 [btree]=3 [gss_scenario]=3 [lanelet2]=3)
# The executions of a CI run (--ci), seeds included: 25 s each under ASan+UBSan at the rates of a
# clean CI run with the counts before (2026-12-02, two targets at a time: sdv_frontend 67 exec/s,
# lanelet2 90, sweep_rows 117, gss_scenario 150, run_dir 153, run_diff 157, btree 160,
# cosim_frame 166, recording 230, ir_reader 468, sweep_results 937). The seeds are the slow
# inputs, so these counts take longer: 9-55 s a target, 167 s for the stage over both cores
# (sdv_frontend 55 s, btree 41, gss_scenario 37, lanelet2 35; was 231 s).
declare -A ci_runs=([sdv_frontend]=1700 [ir_reader]=12000 [btree]=4000 [gss_scenario]=3800
                    [lanelet2]=2300 [cosim_frame]=3000 [sweep_results]=15000 [recording]=3000
                    [run_dir]=3800 [run_diff]=3000 [sweep_rows]=3000)

usage() {
    sed -n '5,8p' "$0" >&2
    exit 2
}

target="" minutes=10 preset=fuzz runs="" record="" corpus="" jobs=1 keep_going=0 ci=0 build_it=1 resume=0
max_parts="" part_minutes=30 part_runs="" state_dir="" build_dir="" stop=0
given=("$@")
number() { [[ "$2" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: $1 takes a positive whole number, not '$2'" >&2; usage; }; }
while [ $# -gt 0 ]; do
    case $1 in
        --no-sanitizers) preset=fuzz-nosan ;;
        --runs) runs=${2:?}; number "$1" "$runs"; shift ;;
        --record) record=1 ;;
        --keep-going) keep_going=1 ;;
        --resume) resume=1 ;;
        --parts) max_parts=${2:?}; number "$1" "$max_parts"; shift ;;
        --part-minutes) part_minutes=${2:?}; number "$1" "$part_minutes"; shift ;;
        --part-runs) part_runs=${2:?}; number "$1" "$part_runs"; shift ;;
        --state-dir) state_dir=$(realpath -m "${2:?}"); shift ;;
        --build-dir) build_dir=$(realpath -m "${2:?}"); shift ;;
        --ci) ci=1; build_it=0 ;;
        --no-build) build_it=0 ;;
        --no-record) record=0 ;;
        --stop) stop=1 ;;
        --corpus) corpus=${2:?}; shift ;;
        --jobs) jobs=${2:?}; number "$1" "$jobs"; shift ;;
        -h|--help) usage ;;
        -*) echo "fuzz.sh: unknown option $1" >&2; usage ;;
        *)
            if [ -z "$target" ]; then target=$1; else minutes=$1; number minutes "$minutes"; fi ;;
    esac
    shift
done
[ -n "$target" ] || usage
if [ -z "${max_len[$target]:-}" ]; then
    echo "fuzz.sh: unknown target '$target' (targets: ${targets[*]})" >&2
    exit 2
fi
[ "$ci" = 0 ] || runs=${ci_runs[$target]}
if [ "$stop" = 1 ] && [ -n "$runs" ]; then
    echo "fuzz.sh: --stop stops the campaign running: it takes no bound" >&2
    usage
fi
if [ "$resume" = 1 ] && [ "$stop" = 0 ] && { [ -z "$runs" ] || [ "$ci" = 1 ]; }; then
    echo "fuzz.sh: --resume goes with --runs N" >&2
    usage
fi
[ -n "$record" ] || { [ -n "$runs" ] && record=0 || record=1; }

build=${build_dir:-$root/build/$preset}
cd "$root"
# build_target DIR: builds fuzz_TARGET in the build directory DIR of the source tree above it.
build_target() {
    local dir=$1 src=${1%/build/"$preset"}
    if [ ! -f "$dir/CMakeCache.txt" ]; then
        if [ "$src" = "$dir" ]; then
            echo "fuzz.sh: $dir is no configured build (cmake --preset $preset configures build/$preset)" >&2
            return 1
        fi
        # The shared data by its real path, as the build in the checkout names it.
        (cd "$src" && cmake --preset "$preset" -DSDV_FUZZ_SHARED_DIR="$(realpath -m "$root/../shared")" >/dev/null) || return 1
    fi
    mkdir -p "$dir"
    cmake --build "$dir" --target "fuzz_$target" -j "$(nproc)" >"$dir/fuzz-build-$target.log" 2>&1 || {
        tail -30 "$dir/fuzz-build-$target.log" >&2
        echo "fuzz.sh: building fuzz_$target failed (log: $dir/fuzz-build-$target.log)" >&2
        return 1
    }
}
exe=$build/fuzz/fuzz_$target

# A campaign (--resume): its copy of the executable, corpus and state on this machine, and the
# committed state it goes on from on any machine.
campaign=$build/campaigns/$target
saved=$root/tests/fuzz/campaigns/$preset/$target
if [ -n "$state_dir" ]; then
    campaign=$state_dir/machine/$preset/$target saved=$state_dir/$preset/$target
fi
stop_grace=${SDV_FUZZ_STOP_GRACE:-30}
# running_script: the PID of the script running this campaign on this machine (its file
# "running", written when its parts start), if that process is still such a script; else empty.
running_script() {
    local pid
    pid=$(cat "$campaign/running" 2>/dev/null) || return 0
    if [[ "$pid" =~ ^[0-9]+$ ]] && [ "$pid" != "$$" ] &&
       tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null | grep -Eq "fuzz\.sh $target( |\$)"; then
        echo "$pid"
    fi
}
# --stop: SIGTERM to that script alone (not `pkill -f`, which also hits its subshells), then wait
# for it to end, bounded by the fuzzer's grace and a minute to count and save the part.
if [ "$stop" = 1 ]; then
    pid=$(running_script)
    if [ -z "$pid" ]; then
        echo "fuzz.sh: no campaign of $target ($preset) is running on this machine" >&2
        exit 1
    fi
    echo "fuzz.sh: stopping the campaign of $target ($preset): SIGTERM to its script, process $pid" >&2
    kill -TERM "$pid"
    for _ in $(seq $(((stop_grace + 60) * 2))); do
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.5
    done
    if kill -0 "$pid" 2>/dev/null; then
        echo "fuzz.sh: the campaign's script (process $pid) did not end within $((stop_grace + 60)) s" >&2
        exit 2
    fi
    if [ -f "$saved" ]; then
        # shellcheck disable=SC1090
        . "$saved"
        echo "fuzz.sh: campaign of fuzz_$target stopped: $c_execs of $c_runs executions in $c_parts part(s)," \
             "$c_findings finding(s); run its command again to go on" >&2
    fi
    exit 0
fi
if [ "$resume" = 1 ] && pid=$(running_script) && [ -n "$pid" ]; then
    echo "fuzz.sh: the campaign of $target ($preset) is already running on this machine (process $pid)" >&2
    exit 2
fi
# c_fork_parts: how many of the parts ran in fork mode (--keep-going); a campaign may change modes.
c_runs=0 c_execs=0 c_seconds=0 c_findings=0 c_parts=0 c_fork_parts=0 c_machines=0 c_commit="" c_clean=0
c_sha256=""
c_toolchain="" c_started="" c_last="" c_command="" c_srcdir=""
save_state() {
    local f
    c_last=$(date -u +%Y-%m-%d)
    mkdir -p "$(dirname "$saved")"
    for f in "$campaign/state" "$saved"; do
        printf '# A fuzz campaign of scripts/fuzz.sh --resume (tests/fuzz/README.md); written by the script.\n' >"$f.part"
        printf 'c_%s=%q\n' runs "$c_runs" execs "$c_execs" seconds "$c_seconds" findings "$c_findings" \
            parts "$c_parts" fork_parts "$c_fork_parts" machines "$c_machines" commit "$c_commit" \
            clean "$c_clean" sha256 "$c_sha256" \
            toolchain "$c_toolchain" started "$c_started" last "$c_last" command "$c_command" \
            srcdir "$c_srcdir" >>"$f.part"
        mv -f "$f.part" "$f"
    done
}
sha() { sha256sum "$1" | cut -c1-64; }
# The state beside the checkout is the campaign's: it is written with the machine's copy after
# every part and removed at the end. A copy without it is of a campaign that was ended or
# deleted there (or of a script before committed states): left aside, not resumed.
if [ "$resume" = 1 ] && [ -f "$campaign/state" ] && [ ! -f "$saved" ]; then
    echo "fuzz.sh: $campaign is of a campaign without a state in $(dirname "$saved") (ended or deleted there):" \
         "starting a new campaign" >&2
    rm -rf "$campaign"
fi
# A campaign under way on this machine runs its own copy: nothing to build.
if [ "$build_it" = 1 ] && { [ "$resume" = 0 ] || [ ! -f "$campaign/state" ]; }; then
    build_target "$build" || exit 2
fi
if [ "$resume" = 1 ]; then
    if [ -f "$campaign/state" ] || [ -f "$saved" ]; then
        from=$saved
        [ ! -f "$campaign/state" ] || from=$campaign/state
        # shellcheck disable=SC1090
        . "$from"
        if [ "$c_runs" != "$runs" ]; then
            echo "fuzz.sh: $from is a campaign of $c_runs runs, not $runs: finish it, or delete it" \
                 "(and $campaign) to start over" >&2
            exit 2
        fi
    fi
    if [ -f "$campaign/state" ]; then
        exe=$campaign/fuzz_$target
        echo "fuzz.sh: resuming $campaign: part $((c_parts + 1)), $c_execs of $c_runs executions done" >&2
    elif [ -f "$saved" ]; then
        # Another machine ran the parts so far: find the executable again by its bytes.
        echo "fuzz.sh: resuming the campaign of $saved on this machine: part $((c_parts + 1))," \
             "$c_execs of $c_runs executions done; its executable was built from $c_commit" >&2
        if [ ! -x "$exe" ] || [ "$(sha "$exe")" != "$c_sha256" ]; then
            if [ "$c_clean" != 1 ]; then
                echo "fuzz.sh: the campaign's executable was built from $c_commit with uncommitted changes:" \
                     "it cannot be built again, and $exe is not it; delete $saved to start over" >&2
                exit 2
            fi
            src=$root/build/campaign-src/$c_commit
            if [ ! -f "$src/CMakePresets.json" ]; then
                rm -rf "$src" && mkdir -p "$src"
                git -C "$root" archive "$c_commit" | tar -x -C "$src" || {
                    rm -rf "$src"
                    echo "fuzz.sh: no commit $c_commit in this repository: the campaign cannot go on;" \
                         "delete $saved to start over" >&2
                    exit 2
                }
            fi
            # Sanitizers compile the source's paths into the executable (UBSan's type names and
            # locations, ASan's globals), so the source is built where the campaign's was: in a
            # private mount namespace, over the campaign's directory (root only). Without one, a
            # build in place is the same bytes only without sanitizers (-ffile-prefix-map).
            if [ -n "$c_srcdir" ] && unshare -m --propagation private true 2>/dev/null; then
                echo "fuzz.sh: building fuzz_$target of $c_commit from $src, as $c_srcdir" >&2
                mkdir -p "$src/build/$preset"
                # The campaign's source directory may be gone from this machine: an empty
                # directory serves as the mount point while the build runs.
                made_srcdir=0
                [ -d "$c_srcdir" ] || { mkdir -p "$c_srcdir" && made_srcdir=1; }
                unshare -m --propagation private bash -c \
                    'mount --bind "$1" "$2" && cd "$2" && cmake --preset "$3" -DSDV_FUZZ_SHARED_DIR="$4" >/dev/null &&
                     cmake --build "build/$3" --target "fuzz_$5" -j "$(nproc)"' \
                    _ "$src" "$c_srcdir" "$preset" "$(realpath -m "$root/../shared")" "$target" \
                    >"$src/build/$preset/fuzz-build-$target.log" 2>&1 || {
                    tail -30 "$src/build/$preset/fuzz-build-$target.log" >&2
                    echo "fuzz.sh: building fuzz_$target of $c_commit failed" >&2
                    [ "$made_srcdir" = 0 ] || rmdir "$c_srcdir"
                    exit 2
                }
                [ "$made_srcdir" = 0 ] || rmdir "$c_srcdir"
            else
                echo "fuzz.sh: building fuzz_$target of $c_commit in $src" >&2
                build_target "$src/build/$preset" || exit 2
            fi
            exe=$src/build/$preset/fuzz/fuzz_$target
            if [ "$(sha "$exe")" != "$c_sha256" ]; then
                echo "fuzz.sh: fuzz_$target built again from $c_commit is not the campaign's executable" \
                     "(SHA-256 $(sha "$exe"), not $c_sha256; the campaign's toolchain: $c_toolchain;" \
                     "this one: $(clang++ --version | head -1)): the campaign cannot go on; delete $saved" \
                     "to start over" >&2
                exit 2
            fi
        fi
        rm -rf "$campaign" && mkdir -p "$campaign/work"
        cp -p "$exe" "$campaign/fuzz_$target"
        exe=$campaign/fuzz_$target
        c_machines=$((c_machines + 1))
        save_state
    else
        if [ ! -x "$exe" ]; then
            echo "fuzz.sh: no $exe: build the $preset preset first" >&2
            exit 2
        fi
        rm -rf "$campaign" && mkdir -p "$campaign/work"
        cp -p "$exe" "$campaign/fuzz_$target"
        exe=$campaign/fuzz_$target
        c_runs=$runs c_machines=1 c_started=$(date -u +%Y-%m-%d) c_command="scripts/fuzz.sh ${given[*]}"
        # The source the executable was built from (--build-dir may be another checkout's build).
        # (none without a CMakeCache.txt, as a directory holding only fuzz/fuzz_TARGET: this checkout)
        c_srcdir=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" 2>/dev/null) || c_srcdir=""
        c_srcdir=${c_srcdir:-$root}
        # The commit: that checkout's HEAD, when no tracked file differs from it (but the ones
        # this script writes); otherwise the campaign can go on only where the same bytes are
        # built (it cannot be built again from a commit).
        c_commit=$(git -C "$c_srcdir" rev-parse --short=12 HEAD 2>/dev/null) || c_commit=unknown
        c_clean=1
        if [ "$c_commit" = unknown ] ||
           [ -n "$(git -C "$c_srcdir" status --porcelain --untracked-files=no -- . ':!tests/fuzz/campaigns' \
                   ':!docs/reliability.md')" ]; then
            c_clean=0
            echo "fuzz.sh: warning: $c_srcdir has uncommitted changes: this campaign can go on only where" \
                 "its executable's bytes are built again (commit first to run it on any machine)" >&2
        fi
        c_sha256=$(sha "$exe")
        c_toolchain=$(clang++ --version | head -1)
        save_state
    fi
fi
if [ ! -x "$exe" ]; then
    echo "fuzz.sh: no $exe: build the $preset preset first" >&2
    exit 2
fi

# The seed corpus: gathered once (delete the directory to gather again). The inputs are
# compiled, recorded and swept by the first `sdv` found (an uninstrumented one is faster). Runs
# started together (two campaigns, one a core) gather it once: the first holds the lock, the others
# wait for it and find the corpus made.
if [ -z "$corpus" ]; then
    corpus=$build/corpus
    (
        flock 9
        if [ ! -d "$corpus/$target" ]; then
            sdv_dir=""
            for d in build/ci build/release build/dev build/fuzz; do
                if [ -x "$d/sdv" ]; then sdv_dir=$d; break; fi
            done
            # Without sanitizers the preset instruments every object for coverage but links no
            # fuzzer runtime into `sdv`, so it cannot link there: the release preset builds it.
            # The ASan runtime of the fuzz preset carries the coverage callbacks: its own links.
            sdv_build=$build
            [ "$preset" = fuzz ] || sdv_build=$root/build/release
            if [ -z "$sdv_dir" ]; then
                echo "fuzz.sh: building sdv in $sdv_build for the seed corpus" >&2
                { [ "$preset" = fuzz ] || [ -f "$sdv_build/CMakeCache.txt" ] || cmake --preset release >/dev/null; } &&
                    cmake --build "$sdv_build" --target sdv -j "$(nproc)" >>"$build/fuzz-build-$target.log" 2>&1 &&
                    sdv_dir=$sdv_build ||
                    echo "fuzz.sh: building sdv failed (log: $build/fuzz-build-$target.log)" >&2
            fi
            scripts/fuzz-corpus.sh "${sdv_dir:-$build}" "$corpus" >&2
        fi
    ) 9>"$build/corpus.lock" || exit
fi
# The fuzzer runs in a scratch directory: every path it is given must be absolute.
corpus=$(realpath -m "$corpus")

work=$build/fuzz-work/$target
[ "$resume" = 0 ] || work=$campaign/work
findings=$build/findings/$target
mkdir -p "$work" "$findings"
logs=$(mktemp -d)
# Only this script's own process removes the logs: a subshell of it (the fuzzer's, before its exec)
# killed by a signal runs this trap too, and removed them under the part being counted.
running=""
trap '[ "$BASHPID" != "$$" ] || rm -rf "$logs" ${running:+"$running"}' EXIT
# SIGTERM or SIGINT to the script stops the fuzzer (as one to the fuzzer's main process does) and
# ends the run after the part under way is counted.
# libFuzzer's handler of SIGTERM prints its stats, removes its fork directory and exits; it
# allocates and calls opendir in the handler (not async-signal-safe: it can block on a lock the
# signal interrupted), so a fuzzer still running stop_grace seconds after the signal
# (SDV_FUZZ_STOP_GRACE, default 30) is killed: a stopped run never waits on its fuzzer without
# bound. The watchdog holds none of this script's descriptors (a test's output pipe stays free).
fuzzer_pid="" stop_asked=0 watchdog_pid=""
stop_fuzzer() {
    [ -n "$fuzzer_pid" ] || return 0
    kill -TERM "$fuzzer_pid" 2>/dev/null || true
    if [ -z "$watchdog_pid" ]; then
        (sleep "$stop_grace"; kill -KILL "$fuzzer_pid") </dev/null >/dev/null 2>&1 &
        watchdog_pid=$!
    fi
}
trap 'stop_asked=1; stop_fuzzer' TERM INT

# An input over 1 s is a finding of a long run (docs/reliability.md); CI only fails on a hang
# (60 s): its verdict must not depend on how busy the machine is.
per_input=1
[ "$preset" != fuzz ] || per_input=${timeout_sanitized[$target]:-1}
[ "$ci" = 0 ] || per_input=60
common=(-max_len="${max_len[$target]}" -timeout="$per_input" -rss_limit_mb=2048
        -dict="$root/tests/fuzz/dict/$target.dict" -artifact_prefix="$findings/" -print_final_stats=1
        -interrupted_exitcode=72)
# One process by default (as -jobs=1 -workers=1); --jobs N runs N jobs side by side, each in a
# child process writing fuzz-<k>.log in the working directory; --keep-going runs --jobs
# children at a time in fork mode.
if [ "$keep_going" = 1 ]; then
    common+=(-fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
elif [ "$jobs" -gt 1 ]; then
    common+=(-jobs="$jobs" -workers="$jobs")
fi

# fuzz_once ARGS...: one run of the fuzzer with the bound ARGS; sets status, seconds, execs, rate,
# cov, ft, crashes (artifacts written), stopped (by a signal, not a finding) and new_findings.
fuzz_once() {
    rm -f "$logs"/*.log
    touch "$logs/start"
    local before after
    before=$(find "$findings" -type f | wc -l)
    echo "fuzz.sh: fuzz_$target ($preset) $* over $corpus/$target" >&2
    status=0
    local started=$SECONDS
    # A signal that came before the part started ends it before the fuzzer starts (as a fuzzer
    # stopped at once: exit status 72, no execution).
    if [ "$stop_asked" = 1 ]; then
        : >"$logs/main.log"
        status=72
    else
        # The subshell drops this script's traps first: one that ran a signal's trap would go on
        # to start the fuzzer, which nothing would stop before the watchdog.
        (trap - TERM INT EXIT
         cd "$logs" && UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
            exec "$exe" "$@" "${common[@]}" "$work" "$corpus/$target" >"$logs/main.log" 2>&1) &
        fuzzer_pid=$!
        # A signal that came while the fuzzer was starting stops it now.
        [ "$stop_asked" = 0 ] || stop_fuzzer
    fi
    while [ -n "$fuzzer_pid" ]; do
        local st=0
        wait "$fuzzer_pid" || st=$?
        # A signal trapped by this script interrupts wait, not the fuzzer: wait again.
        if [ "$st" -gt 128 ] && kill -0 "$fuzzer_pid" 2>/dev/null; then continue; fi
        status=$st
        break
    done
    fuzzer_pid=""
    if [ -n "$watchdog_pid" ]; then
        kill "$watchdog_pid" 2>/dev/null || true
        watchdog_pid=""
        [ "$status" -ne 137 ] || echo "fuzz.sh: fuzz_$target did not stop within $stop_grace s of SIGTERM: killed" >&2
    fi
    seconds=$((SECONDS - started))
    # A child of fork mode outlives its parent stopped by a signal (it ran on for minutes): stop
    # every process of this executable still running.
    pkill -TERM -f "^$exe( |\$)" 2>/dev/null || true
    cat "$logs"/fuzz-*.log >"$logs/all.log" 2>/dev/null || true
    cat "$logs/main.log" >>"$logs/all.log"
    after=$(find "$findings" -type f | wc -l)
    crashes=$((after - before))
    new_findings=$(find "$findings" -type f -newer "$logs/start")

    # The numbers of the run: libFuzzer's final stats (summed over jobs) and the coverage of its
    # last status line; in fork mode its last "#N: cov: ... time: Ts" line; of a fuzzer killed
    # before its final stats, the count of its last status line (a lower bound).
    read -r execs rate cov ft < <(awk '
        /stat::number_of_executed_units:/ { execs += $2 }
        /stat::average_exec_per_sec:/ { rate += $2 }
        /^#[0-9]+:?[[:space:]].*cov: [0-9]+ ft: [0-9]+/ {
            for (i = 1; i < NF; i++) { if ($i == "cov:") c = $(i + 1); if ($i == "ft:") f = $(i + 1); if ($i == "time:") t = $(i + 1) }
            if (c + 0 > cov) cov = c + 0; if (f + 0 > ft) ft = f + 0
            n = substr($1, 2) + 0
            if ($1 ~ /:$/) { if (n > fork_execs) fork_execs = n; sub(/s$/, "", t); fork_time = t + 0 }
            else if (n > status_execs) status_execs = n }
        END { if (execs == 0 && fork_execs > 0) { execs = fork_execs; rate = fork_time > 0 ? fork_execs / fork_time : 0 }
              if (execs == 0) execs = status_execs
              printf "%d %d %d %d\n", execs, rate, cov, ft }' "$logs/all.log")
    grep -E "^(INFO: (seed|.*files found)|#[0-9]+[[:space:]]+(INITED|DONE)|stat::|==[0-9]+==ERROR|SUMMARY|ALARM|sdv fuzz:)" \
        "$logs/all.log" | head -40 >&2 || true
    # Exit status 72 without an artifact: stopped by SIGINT or SIGTERM, not a finding; so is
    # 143 when this script passed a signal on before the fuzzer could handle it, and 137 when the
    # fuzzer was killed after not stopping within stop_grace.
    stopped=0
    if { [ "$status" -eq 72 ] || { [ "$stop_asked" = 1 ] && { [ "$status" -eq 143 ] || [ "$status" -eq 137 ]; }; }; } &&
        [ "$crashes" -eq 0 ]; then
        stopped=1 status=0
        echo "fuzz.sh: fuzz_$target stopped by a signal" >&2
    fi
    if [ "$keep_going" = 1 ] && [ "$crashes" -gt 0 ]; then
        echo "fuzz.sh: $crashes FINDING(s) in fuzz_$target:" >&2
        printf '%s\n' "$new_findings" | sed 's/^/    /' >&2
    elif [ "$status" -ne 0 ] || [ "$crashes" -gt 0 ]; then
        echo "fuzz.sh: FINDING in fuzz_$target: exit status $status; artifacts:" >&2
        printf '%s\n' "$new_findings" | sed '/^$/d; s/^/    /' >&2
        grep -E -m5 "ERROR|runtime error|sdv fuzz:|ALARM" "$logs/all.log" | sed 's/^/    /' >&2 || true
        [ "$crashes" -gt 0 ] || crashes=1
    fi
    # A timeout is measured in wall-clock time: on a machine busy with other work an input of 0.4 s
    # can pass 1 s. Each new timeout artifact is replayed three times in one process and the fastest
    # of the last two (the first pays the target's one-time set-up) is printed next to the limit,
    # so that a load artifact is told from a slow input. It stays counted as a finding.
    local f ms
    for f in $(printf '%s\n' "$new_findings" | grep '/timeout-' || true); do
        ms=$("$exe" "$f" "$f" "$f" 2>&1 |
             awk '/^Executed .* in [0-9]+ ms/ { n++; if (n > 1 && (best == "" || $(NF - 1) + 0 < best)) best = $(NF - 1) + 0 }
                  END { print best == "" ? "?" : best }') || ms="?"
        echo "fuzz.sh: $(basename "$f") replays alone in $ms ms (limit ${per_input} s)" >&2
    done
    echo "fuzz.sh: fuzz_$target: $execs executions, $rate exec/s, cov $cov ft $ft, $crashes finding(s)" >&2
}

# record_row: rewrites the row of this target and build in the table of runs of docs/reliability.md.
# It and record_campaigns hold a lock on the file while they read and rewrite it in place: runs side
# by side (a campaign a core) would otherwise read one another's half-written file.
record_row() {
    local build_kind bound_text parts_text row
    build_kind=$([ "$preset" = fuzz ] && echo "ASan+UBSan" || echo "no sanitizers")
    bound_text=${runs:+"$runs runs"}
    bound_text=${bound_text:-"$minutes min"}
    parts_text=$([ "$c_parts" = 1 ] && echo "one part" || echo "$c_parts parts")
    if [ "$resume" = 1 ]; then
        local machines_text
        machines_text=$([ "$c_machines" = 1 ] && echo "" || echo " on $c_machines machines")
        bound_text="$bound_text in $parts_text$machines_text (one executable, built from $c_commit)"
    fi
    if [ "$resume" = 0 ]; then
        [ "$keep_going" = 0 ] || bound_text="$bound_text, fork mode"
    elif [ "$c_fork_parts" -gt 0 ] && [ "$c_fork_parts" -ge "$c_parts" ]; then
        bound_text="$bound_text, fork mode"
    elif [ "$c_fork_parts" -gt 0 ]; then
        bound_text="$bound_text, $c_fork_parts of them in fork mode"
    fi
    [ "$per_input" = 1 ] || bound_text="$bound_text, ${per_input} s per input"
    [ "$stopped" = 0 ] || [ "$resume" = 1 ] || bound_text="$bound_text, stopped by a signal"
    row="| $target | $build_kind | $execs | $rate | $cov | $ft | $crashes | $bound_text | $(date -u +%Y-%m-%d) |"
    flock "$root/docs/reliability.md" \
        python3 - "$root/docs/reliability.md" "$target" "$build_kind" "$row" <<'PY'
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
}

# record_campaigns: rewrites the table of campaigns under way in docs/reliability.md from the
# committed states (tests/fuzz/campaigns).
record_campaigns() {
    flock "$root/docs/reliability.md" python3 - "$root/docs/reliability.md" "$root/tests/fuzz/campaigns" <<'PY'
import pathlib, shlex, sys
doc, states = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
begin, end = "<!-- fuzz-campaigns:begin -->", "<!-- fuzz-campaigns:end -->"
rows = ["| target | build | executions | of | parts | machines | hours | findings | executable built from | started | last part | to go on |",
        "|---|---|---:|---:|---:|---:|---:|---:|---|---|---|---|"]
kinds = {"fuzz": "ASan+UBSan", "fuzz-nosan": "no sanitizers"}
for f in sorted(states.glob("*/*"), key=lambda f: (f.name, f.parent.name)):
    if f.is_dir() or f.parent.name not in kinds:
        continue
    s = {}
    for line in f.read_text().splitlines():
        if line.startswith("c_") and "=" in line:
            k, v = line.split("=", 1)
            s[k[2:]] = " ".join(shlex.split(v)) if v else ""
    # The command that goes on: the one that started the campaign, less the options of that run
    # alone (how many parts, how long) and of that machine's directories.
    words, go_on = shlex.split(s.get("command", "")), []
    while words:
        w = words.pop(0)
        if w in ("--parts", "--part-minutes", "--part-runs", "--build-dir", "--corpus"):
            words = words[1:]
        else:
            go_on.append(w)
    rows.append("| {} | {} | {} | {} | {} | {} | {:.1f} | {} | {}{} | {} | {} | `{}` |".format(
        f.name, kinds[f.parent.name], s.get("execs", "?"), s.get("runs", "?"), s.get("parts", "?"),
        s.get("machines", "?"), int(s.get("seconds", "0")) / 3600, s.get("findings", "?"), s.get("commit", "?"),
        "" if s.get("clean") == "1" else " (uncommitted changes)", s.get("started", ""), s.get("last", ""),
        shlex.join(go_on).replace("|", "\\|")))
if len(rows) == 2:
    rows = ["None."]
text = doc.read_text(encoding="utf-8")
if begin not in text:
    sys.exit("docs/reliability.md has no " + begin)
head, rest = text.split(begin, 1)
_, tail = rest.split(end, 1)
doc.write_text(head + begin + "\n" + "\n".join(rows) + "\n" + end + tail, encoding="utf-8")
PY
}

if [ "$resume" = 0 ]; then
    if [ -n "$runs" ]; then
        # A bounded run starts from the seeds alone, so that it is the same run every time.
        rm -rf "$work" && mkdir -p "$work"
        fuzz_once -runs="$runs" -seed=1
    else
        fuzz_once -max_total_time=$((minutes * 60))
    fi
    [ "$record" = 0 ] || record_row
    [ "$status" -eq 0 ] && [ "$crashes" -eq 0 ]
    exit
fi

# The parts of a campaign: each from the corpus of the parts before on this machine (another
# seed each: the part's number), its executions, time and findings added to the state. One
# script at a time runs a campaign (checked above); its PID is in the campaign's file "running".
running=$campaign/running
echo "$$" >"$running"
parts_run=0 any_finding=0
while [ "$c_execs" -lt "$c_runs" ] && [ "$stop_asked" = 0 ]; do
    if [ -n "$max_parts" ] && [ "$parts_run" -ge "$max_parts" ]; then break; fi
    left=$((c_runs - c_execs))
    [ -z "$part_runs" ] || [ "$part_runs" -ge "$left" ] || left=$part_runs
    fuzz_once -runs="$left" -seed="$((c_parts + 1))" -max_total_time=$((part_minutes * 60))
    parts_run=$((parts_run + 1))
    if [ "$execs" -eq 0 ] && [ "$crashes" -eq 0 ]; then
        # Stopped before it executed an input: no part to count.
        [ "$stopped" = 0 ] || break
        echo "fuzz.sh: a part of the campaign executed no input (log above); the campaign stops" >&2
        exit 2
    fi
    c_parts=$((c_parts + 1)) c_execs=$((c_execs + execs)) c_seconds=$((c_seconds + seconds))
    c_findings=$((c_findings + crashes))
    [ "$keep_going" = 0 ] || c_fork_parts=$((c_fork_parts + 1))
    if [ -n "$new_findings" ]; then
        # The artifacts go beside the committed state: they outlive this machine.
        mkdir -p "$saved.findings"
        printf '%s\n' "$new_findings" | while IFS= read -r f; do cp -p "$f" "$saved.findings/"; done
    fi
    if [ "$crashes" -gt 0 ]; then any_finding=1; fi
    save_state
    echo "fuzz.sh: campaign of fuzz_$target: $c_execs of $c_runs executions in $c_parts part(s)," \
         "$c_findings finding(s)" >&2
    [ "$record" = 0 ] || [ -n "$state_dir" ] || [ "$c_execs" -ge "$c_runs" ] || record_campaigns
    # Without --keep-going a finding stops the campaign, as it stops a run.
    if [ "$crashes" -gt 0 ] && [ "$keep_going" = 0 ]; then break; fi
    if [ "$stopped" = 1 ]; then break; fi
done
if [ "$c_execs" -ge "$c_runs" ]; then
    echo "fuzz.sh: campaign of fuzz_$target done: $c_execs executions in $c_parts part(s) on $c_machines" \
         "machine(s), $c_findings finding(s)" >&2
    execs=$c_execs crashes=$c_findings
    rate=$((c_seconds > 0 ? c_execs / c_seconds : 0))
    rm -f "$running" && running=""
    mv "$campaign" "$campaign.done-$(date -u +%Y%m%d%H%M%S)"
    # The committed state goes (a finished campaign is its row); its findings stay until triaged.
    rm -f "$saved"
    if [ "$record" = 1 ] && [ -z "$state_dir" ]; then
        record_row
        record_campaigns
    fi
    [ "$c_findings" -eq 0 ]
    exit
fi
echo "fuzz.sh: campaign of fuzz_$target: run the same command to go on" >&2
[ "$any_finding" = 0 ]
exit
}
