#!/usr/bin/env bash
# The campaign benchmark's sweep through a local Slurm (issue 16): the cut-in of
# examples/sweeps/cut_in_search.sdv as a Latin hypercube of N variants (default 1,000), swept
# locally with 2 jobs and as a Slurm job array of K tasks (default 4 and 20) on the single-node
# cluster of scripts/slurm-local.sh; prints the wall times and checks the results are identical.
#   bench/slurm_sweep.sh SDV [N]
set -euo pipefail
sdv=$(realpath "$1")
n=${2:-1000}
root=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d /tmp/sdv-slurm-bench.XXXXXX)
state=$tmp/cluster
trap 'bash "$root/scripts/slurm-local.sh" down "$state" > /dev/null 2>&1 || true; rm -rf "$tmp"' EXIT
sed "s/sample latin 200/sample latin $n/" "$root/examples/sweeps/cut_in_search.sdv" > "$tmp/sweep.sdv"
ms() { date +%s%3N; }
t0=$(ms); "$sdv" sweep "$tmp/sweep.sdv" -o "$tmp/local" --jobs 2 > /dev/null || true; t1=$(ms)
echo "local sweep, 2 jobs:        $n variants in $((t1 - t0)) ms"
eval "$(bash "$root/scripts/slurm-local.sh" up "$state")"
for k in 4 20; do
    t0=$(ms); "$sdv" sweep "$tmp/sweep.sdv" -o "$tmp/slurm$k" --slurm --array-tasks $k > /dev/null || true; t1=$(ms)
    same=no
    cmp -s "$tmp/local/results.csv" "$tmp/slurm$k/results.csv" && cmp -s "$tmp/local/summary.json" "$tmp/slurm$k/summary.json" && same=yes
    echo "Slurm job array, $k tasks:  $n variants in $((t1 - t0)) ms (submit, wait, merge); results identical: $same"
done
