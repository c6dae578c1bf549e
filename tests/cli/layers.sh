#!/usr/bin/env bash
# The layer rule of docs/architecture.md, checked on the includes of every source file:
#   runtime/ never includes compiler/ (the IR, runtime/ir, is the contract between them);
#   runtime/catalog includes only itself; runtime/ir only the catalog;
#   runtime/road and runtime/planner never include runtime/sim, runtime/bt or runtime/io;
#   runtime/bt never includes runtime/sim or runtime/io; runtime/sim never includes runtime/io,
#   runtime/cosim or runtime/campaign; runtime/io never includes runtime/cosim or runtime/campaign;
#   runtime/campaign and runtime/cosim never include each other; runtime/realism includes only
#   runtime/road (and the libraries), never the simulation;
#   cli/ is the only place that includes both compiler/ and runtime/io.
# Usage: layers.sh REPO_ROOT
set -u
root=$1
fail=0
check() {  # check DIR PATTERN WHY
    local hits
    hits=$(grep -rnE "^#include \"($2)" "$root/$1" --include='*.h' --include='*.cpp' 2>/dev/null)
    if [ -n "$hits" ]; then
        echo "FAIL: $3"
        echo "$hits" | sed "s|$root/||"
        fail=1
    fi
}
check runtime 'compiler/' "runtime/ includes compiler/"
check runtime/catalog 'runtime/(ir|road|planner|bt|sim|io)/' "runtime/catalog includes a layer above it"
check runtime/ir 'runtime/(road|planner|bt|sim|io)/' "runtime/ir includes a layer above it"
check runtime/road 'runtime/(planner|bt|sim|io)/' "runtime/road includes a layer above it"
check runtime/planner 'runtime/(road|bt|sim|io|ir)/' "runtime/planner includes a layer above it (it works in the Frenet frame only)"
check runtime/bt 'runtime/(sim|io|planner|road)/' "runtime/bt includes a layer above it"
check runtime/sim 'runtime/(io|cosim|campaign)/' "runtime/sim includes runtime/io, runtime/cosim or runtime/campaign (outputs are written by observers)"
check runtime/io 'runtime/(cosim|campaign)/' "runtime/io includes runtime/cosim or runtime/campaign (layers above it)"
check runtime/campaign 'runtime/cosim/' "runtime/campaign includes runtime/cosim (they are siblings)"
check runtime/cosim 'runtime/campaign/' "runtime/cosim includes runtime/campaign (they are siblings)"
check compiler 'runtime/(sim|io|bt|planner)/' "compiler/ includes the simulation"
check runtime/realism 'runtime/(sim|io|bt|planner|cosim|campaign)/' "runtime/realism includes the simulation (it reads recordings and compares paths)"
check runtime/road 'runtime/realism/' "runtime/road includes runtime/realism (a layer above it)"
# No file in runtime/sim above 400 lines: the loop stays in stages.
for f in "$root"/runtime/sim/*.cpp "$root"/runtime/sim/*.h; do
    n=$(wc -l < "$f")
    if [ "$n" -gt 400 ]; then
        echo "FAIL: ${f#$root/} has $n lines (limit 400)"
        fail=1
    fi
done
# Every unit-test file keeps its code in a namespace named after it (segment_grid_test.cpp in
# `namespace segment_grid_test {`): the files of a test executable are compiled in unity batches
# (cmake/SdvTargets.cmake), where two files' helpers of one name would collide.
for f in "$root"/tests/unit/*/*_test.cpp; do
    stem=$(basename "$f" .cpp)
    if ! grep -qx "namespace $stem {" "$f" || ! grep -qx "}  // namespace $stem" "$f"; then
        echo "FAIL: ${f#$root/} does not keep its code in 'namespace $stem { ... }  // namespace $stem'"
        fail=1
    fi
done
[ $fail -eq 0 ] && echo "layers respected"
exit $fail
