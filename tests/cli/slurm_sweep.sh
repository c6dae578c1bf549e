#!/usr/bin/env bash
# `sdv sweep --slurm` on a real Slurm cluster (issue 16): scripts/slurm-local.sh brings up a
# single-node cluster on 127.0.0.1 (state in a temp dir; the EXIT trap always brings it down);
# the sweep run locally (--jobs 2) and as one job array (--slurm --array-tasks 4, the scenario
# named by a relative path) must give
# byte-identical results.csv and summary.json and the same exit code; `slurm-local.sh down` must
# leave no process of the cluster (none of the recorded daemon pids, nothing with the state dir
# in its command line). It runs in CI and never skips: without Slurm and munge it fails.
# Usage: slurm_sweep.sh SDV SCENARIO
set -u
if [ $# -ne 2 ]; then
    echo "usage: slurm_sweep.sh SDV SCENARIO" >&2
    exit 2
fi
here=${BASH_SOURCE[0]%/*}
[ "$here" = "${BASH_SOURCE[0]}" ] && here=.
root=$(cd "$here/../.." && pwd)
local_cluster=$root/scripts/slurm-local.sh
export PATH="$PATH:/usr/sbin:/sbin"
for tool in sbatch squeue slurmctld slurmd munged; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "FAIL: install slurm-wlm and munge (scripts/install-deps.sh --tests)"
        echo "      ($tool not found on PATH=$PATH)"
        exit 1
    fi
done
sdv=$(realpath "$1") || { echo "FAIL: no sdv at $1"; exit 1; }
scenario=$(realpath "$2") || { echo "FAIL: no scenario at $2"; exit 1; }

tmp=$(mktemp -d /tmp/sdv-slurm-sweep.XXXXXX)
state=$tmp/cluster
up=0
cleanup() {
    if [ "$up" = 1 ]; then bash "$local_cluster" down "$state" >/dev/null 2>&1; fi
    rm -rf "$tmp"
}
trap cleanup EXIT
trap 'exit 1' INT TERM
fail=0
pass() { echo "PASS  $*"; }
bad() { echo "FAIL  $*"; fail=1; }
now_ms() { local t=${EPOCHREALTIME/./}; echo $((t / 1000)); }
took() { echo "$(($(now_ms) - $1)) ms"; }
same() {  # same FILE_A FILE_B WHAT
    if cmp -s "$1" "$2"; then pass "$3"; else bad "$3"; diff "$1" "$2" 2>&1 | head -10; fi
}
show_logs() {  # the end of every log that can say why the Slurm sweep failed
    local f
    for f in "$tmp/B.log" "$tmp"/B/slurm/task-*.log "$state"/log/*; do
        [ -s "$f" ] || continue
        echo "----- $f"
        tail -n 15 "$f"
    done
}

# ---- the cluster
t=$(now_ms)
if ! out=$(bash "$local_cluster" up "$state" 2>"$tmp/up.err"); then
    bad "slurm-local.sh up"
    cat "$tmp/up.err"
    exit 1
fi
up=1
eval "$out"
pass "cluster up ($(took "$t")): $(sinfo -h -o '%n %t %c CPUs')"
pids=()
for d in munged slurmctld slurmd; do
    pid=$(cat "$state/$d.pid" 2>/dev/null)
    if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then pids+=("$d:$pid"); else bad "no live $d pid in $state/$d.pid"; fi
done

# ---- the same sweep locally and as a job array
t=$(now_ms)
(cd "${scenario%/*}" && timeout 900 "$sdv" sweep "./${scenario##*/}" -o "$tmp/A" --jobs 2) >"$tmp/A.log" 2>&1
code_a=$?
echo "      local sweep: exit $code_a ($(took "$t"))"
t=$(now_ms)
# The scenario named relative to the working directory, as users do (summary.json names it so):
# the tasks read it by its absolute path, and their rows must still be this sweep's campaign.
(cd "${scenario%/*}" && timeout 900 "$sdv" sweep "./${scenario##*/}" -o "$tmp/B" --slurm --array-tasks 4) >"$tmp/B.log" 2>&1
code_b=$?
echo "      Slurm sweep: exit $code_b ($(took "$t"))"
if [ $code_a -gt 1 ]; then bad "local sweep exit $code_a"; tail -n 20 "$tmp/A.log"; fi
if [ $code_b = "$code_a" ]; then pass "same exit code ($code_b)"; else bad "Slurm sweep exit $code_b, local $code_a"; show_logs; fi
rc_files=("$tmp"/B/slurm/task-*.rc)
tasks=0
[ -e "${rc_files[0]}" ] && tasks=${#rc_files[@]}
if [ "$tasks" = 4 ]; then pass "4 array tasks wrote their exit status"; else bad "$tasks task exit files (expected 4)"; fi
if [ -s "$tmp/A/results.csv" ] && [ -s "$tmp/B/results.csv" ]; then
    pass "results.csv written by both ($(($(wc -l <"$tmp/A/results.csv") - 1)) variants)"
else
    bad "results.csv missing"
    show_logs
fi
same "$tmp/A/results.csv" "$tmp/B/results.csv" "results.csv identical locally and on Slurm"
same "$tmp/A/summary.json" "$tmp/B/summary.json" "summary.json identical locally and on Slurm"

# ---- down leaves nothing
t=$(now_ms)
if bash "$local_cluster" down "$state" 2>"$tmp/down.err"; then
    pass "cluster down ($(took "$t"))"
else
    bad "slurm-local.sh down"
    cat "$tmp/down.err"
fi
up=0
left=()
for entry in "${pids[@]}"; do
    kill -0 "${entry#*:}" 2>/dev/null && left+=("$entry")
done
for d in /proc/[0-9]*; do
    [ "${d#/proc/}" = $$ ] && continue
    words=()
    { mapfile -d '' -t words <"$d/cmdline"; } 2>/dev/null || continue
    [[ " ${words[*]} " == *"$state"* ]] && left+=("${d#/proc/}:${words[*]}")
done
if [ ${#left[@]} = 0 ]; then pass "no process of the cluster is left"; else bad "left running: ${left[*]}"; fi

[ $fail = 0 ] && echo "PASS" || echo "FAIL"
exit $fail
