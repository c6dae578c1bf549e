#!/usr/bin/env bash
# A fuzz campaign in parts (scripts/fuzz.sh --resume, tests/fuzz/README.md), on the ir_reader
# target of a built fuzz preset: parts add up, a machine that lost the campaign's copy finds its
# executable again by its SHA-256 and goes on, the end is counted once, what cannot go on is
# refused with the reason, a machine's copy of an ended campaign is not resumed, and a fuzzer
# deaf to SIGTERM is killed after fuzz.sh's grace.
#   campaign_test.sh SOURCE_DIR BUILD_DIR PRESET
# The state lives in a scratch directory (--state-dir), so nothing of the checkout changes.
set -uo pipefail
root=$1 build=$2 preset=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() {  # check WHAT CONDITION...
    local what=$1
    shift
    if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; fail=1; fi
}
state() { grep "^c_$1=" "$tmp/state/$preset/ir_reader" | cut -d= -f2-; }
# stop PID LOG: SIGTERM to a fuzz.sh started in the background, then its exit status. fuzz.sh kills
# a fuzzer still running 30 s after the signal; a script still running after 120 s of checks is a
# hang: it is killed, LOG says so and the checks after fail (the test never waits without bound).
stop() {
    kill -TERM "$1"
    for _ in $(seq 240); do
        kill -0 "$1" 2>/dev/null || break
        sleep 0.5
    done
    if kill -0 "$1" 2>/dev/null; then
        pkill -KILL -P "$1" 2>/dev/null
        kill -KILL "$1" 2>/dev/null
        echo "fuzz.sh did not end within 120 s of SIGTERM" >>"$2"
    fi
    wait "$1"
}
fuzz() {
    bash "$root/scripts/fuzz.sh" ir_reader "${nosan[@]}" --resume --state-dir "$tmp/state" \
        --build-dir "$build" --corpus "$root/tests/fuzz/corpus" --no-build --no-record "$@"
}
nosan=()
[ "$preset" = fuzz ] || nosan=(--no-sanitizers)
exe=$build/fuzz/fuzz_ir_reader
sha=$(sha256sum "$exe" | cut -c1-64)

# Part 1 of 3,000 executions, 1,000 a part.
fuzz --runs 3000 --part-runs 1000 --parts 1 >"$tmp/1.log" 2>&1
check "the first part ends without a finding" [ $? = 0 ]
check "the first part counts 1,000 executions" [ "$(state execs)" = 1000 ]
check "one part on one machine" [ "$(state parts)/$(state machines)" = 1/1 ]
check "the state names the executable by its SHA-256" [ "$(state sha256)" = "$sha" ]
check "the state names HEAD" [ "$(state commit)" = "$(git -C "$root" rev-parse --short=12 HEAD)" ]
check "this machine has the campaign's copy" cmp -s "$exe" "$tmp/state/machine/$preset/ir_reader/fuzz_ir_reader"

# Another bound is another campaign.
fuzz --runs 4000 --parts 1 >"$tmp/bound.log" 2>&1
check "another bound is refused" [ $? = 2 ]
check "  saying the campaign's bound" grep -q "is a campaign of 3000 runs, not 4000" "$tmp/bound.log"

# Another machine: the committed state alone. The current build is the same bytes, so it goes on.
rm -rf "$tmp/state/machine"
fuzz --runs 3000 --part-runs 1000 --parts 1 >"$tmp/2.log" 2>&1
check "the second part, on another machine, ends without a finding" [ $? = 0 ]
check "  finding the executable by its bytes" grep -q "resuming the campaign of .* on this machine: part 2, 1000 of 3000" "$tmp/2.log"
check "  and counting 2,000 executions in two parts on two machines" \
    [ "$(state execs)/$(state parts)/$(state machines)" = 2000/2/2 ]

# The rest on this machine: the campaign ends, its state goes.
fuzz --runs 3000 >"$tmp/3.log" 2>&1
check "the last part ends the campaign without a finding" [ $? = 0 ]
check "  after 3,000 executions in 3 parts" grep -q "campaign of fuzz_ir_reader done: 3000 executions in 3 part(s) on 2 machine(s), 0 finding(s)" "$tmp/3.log"
check "  and its state is gone" [ ! -e "$tmp/state/$preset/ir_reader" ]

# Stopped by a signal to the script: the part under way is counted, the campaign goes on later.
# (exec: the signal goes to the script itself, not to a subshell around it)
(exec bash "$root/scripts/fuzz.sh" ir_reader "${nosan[@]}" --resume --state-dir "$tmp/state" --build-dir "$build" \
    --corpus "$root/tests/fuzz/corpus" --no-build --no-record --runs 100000000 >"$tmp/4.log" 2>&1) &
script=$!
# The fuzzer is past its start once it has added an input to the campaign's corpus (a guard
# against a hang, not a measure of speed: 600 checks of 0.5 s).
for _ in $(seq 600); do
    [ -z "$(ls -A "$tmp/state/machine/$preset/ir_reader/work" 2>/dev/null)" ] || break
    sleep 0.5
done
stop "$script" "$tmp/4.log"
code=$?
check "a campaign stopped by SIGTERM exits without a finding" [ "$code" = 0 ]
check "  saying so" grep -q "stopped by a signal" "$tmp/4.log"
execs=$(state execs)
counted=0
[ "$execs" -gt 0 ] && [ "$execs" -lt 100000000 ] && counted=1
check "  and counts the executions of its part ($execs)" [ "$counted" = 1 ]
check "  in one part" [ "$(state parts)" = 1 ]

# --stop sends the signal to the campaign's script alone (its PID in the machine's copy), waits for
# it to end and leaves the state whole: a part that executed inputs counted, one stopped before
# its first input not. While the campaign runs, a second script for it is refused.
(exec bash "$root/scripts/fuzz.sh" ir_reader "${nosan[@]}" --resume --state-dir "$tmp/state" --build-dir "$build" \
    --corpus "$root/tests/fuzz/corpus" --no-build --no-record --runs 100000000 >"$tmp/stop.log" 2>&1) &
script=$!
for _ in $(seq 600); do  # until the part's fuzzer runs (a guard against a hang: 600 checks of 0.5 s)
    pgrep -f "^$tmp/state/machine/$preset/ir_reader/fuzz_ir_reader " >/dev/null && break
    sleep 0.5
done
fuzz --runs 100000000 >"$tmp/twice.log" 2>&1
check "a second script for a campaign running is refused" [ $? = 2 ]
check "  naming the one running" grep -q "already running on this machine (process $script)" "$tmp/twice.log"
execs_before=$execs
fuzz --stop >"$tmp/stopped.log" 2>&1
check "--stop stops the campaign's script" [ $? = 0 ]
kill -0 "$script" 2>/dev/null
check "  which has ended when --stop returns" [ $? != 0 ]
stop "$script" "$tmp/stop.log" >/dev/null 2>&1  # reaps it (at once; bounded if --stop failed)
check "  stopped by a signal, not a finding" grep -q "stopped by a signal" "$tmp/stop.log"
check "  its PID file gone" [ ! -e "$tmp/state/machine/$preset/ir_reader/running" ]
grown=$(( $(state execs) > execs_before ))
check "  a part counted if and only if it executed inputs ($execs_before, then $(state execs) in $(state parts))" \
    [ "$(state parts)" = $((1 + grown)) ]
fuzz --stop >"$tmp/none.log" 2>&1
check "--stop with no campaign running says so" [ $? = 1 ]
check "  in words" grep -q "no campaign of ir_reader .* is running on this machine" "$tmp/none.log"

# What cannot go on is refused: a campaign built from uncommitted changes whose bytes are not
# here, and one whose commit this repository does not have.
rm -rf "$tmp/state/machine"
sed -i "s/^c_sha256=.*/c_sha256=$(printf '0%.0s' $(seq 64))/; s/^c_clean=.*/c_clean=0/" "$tmp/state/$preset/ir_reader"
fuzz --runs 100000000 --parts 1 >"$tmp/5.log" 2>&1
check "other bytes of a campaign built from uncommitted changes are refused" [ $? = 2 ]
check "  saying why" grep -q "with uncommitted changes: it cannot be built again" "$tmp/5.log"
sed -i "s/^c_clean=.*/c_clean=1/; s/^c_commit=.*/c_commit=0000000000ff/" "$tmp/state/$preset/ir_reader"
fuzz --runs 100000000 --parts 1 >"$tmp/6.log" 2>&1
check "a campaign of a commit this repository does not have is refused" [ $? = 2 ]
check "  saying why" grep -q "no commit 0000000000ff in this repository" "$tmp/6.log"

# A campaign ended or deleted where its state is kept (its state removed, as by git rm) leaves
# this machine's copy behind: the next run of the same command is a new campaign, not the copy's.
rm -rf "$tmp/state"
fuzz --runs 2000 --part-runs 1000 --parts 1 >"$tmp/7.log" 2>&1
rm "$tmp/state/$preset/ir_reader"
fuzz --runs 2000 --part-runs 1000 --parts 1 >"$tmp/8.log" 2>&1
check "a machine's copy without its state is not resumed" [ $? = 0 ]
check "  saying so" grep -q "without a state in .*: starting a new campaign" "$tmp/8.log"
check "  and the new campaign has one part of 1,000 on one machine" \
    [ "$(state execs)/$(state parts)/$(state machines)" = 1000/1/1 ]
check "  in one process" [ "$(state fork_parts)" = 0 ]
# A part in fork mode (--keep-going) is counted as one: the row names the modes of all parts.
# Fork mode bounds a part's executions only between its jobs (a job may run thousands more than
# -runs on a fast machine), so the campaign's bound is far beyond what two parts can reach.
rm -rf "$tmp/state"
fuzz --runs 100000000 --part-runs 500 --parts 1 >"$tmp/one.log" 2>&1
fuzz --runs 100000000 --part-runs 500 --parts 1 --keep-going >"$tmp/fork.log" 2>&1
check "a part in fork mode is counted as such" [ "$(state parts)/$(state fork_parts)" = 2/1 ]

# A fuzzer that does not stop on SIGTERM (as libFuzzer whose handler blocks) is killed after the
# grace (SDV_FUZZ_STOP_GRACE, here 1 s): fuzz.sh ends, counting its last status line. The stand-in
# ignores SIGTERM and prints one status line.
mkdir -p "$tmp/stubborn/fuzz"
cat >"$tmp/stubborn/fuzz/fuzz_ir_reader" <<'SH'
#!/usr/bin/env bash
trap '' TERM
echo "#77	INITED cov: 5 ft: 6 corp: 1/1b exec/s: 0 rss: 1Mb"
touch "$(dirname "$0")/started"
while :; do sleep 0.1; done
SH
chmod +x "$tmp/stubborn/fuzz/fuzz_ir_reader"
(SDV_FUZZ_STOP_GRACE=1 exec bash "$root/scripts/fuzz.sh" ir_reader --no-sanitizers --build-dir "$tmp/stubborn" \
    --corpus "$root/tests/fuzz/corpus" --no-build --no-record --runs 1000 >"$tmp/9.log" 2>&1) &
script=$!
for _ in $(seq 600); do  # until the stand-in runs (a guard against a hang: 600 checks of 0.5 s)
    [ ! -e "$tmp/stubborn/fuzz/started" ] || break
    sleep 0.5
done
stop "$script" "$tmp/9.log"
code=$?
check "a fuzzer deaf to SIGTERM is killed after the grace" grep -q "did not stop within 1 s of SIGTERM: killed" "$tmp/9.log"
check "  and the run ends stopped, without a finding" [ "$code" = 0 ]
check "  counting its last status line" grep -q "77 executions" "$tmp/9.log"

if [ "$fail" != 0 ]; then
    for f in "$tmp"/*.log; do echo "== $(basename "$f")"; tail -n 15 "$f"; done
    exit 1
fi
echo "campaign in parts: all checks passed"
