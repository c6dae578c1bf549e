#!/usr/bin/env bash
# Newcomer's first command: install, build (release) and compile the headline example, the
# paper's cut-in case study on a built-in road, printing the checked summary. (`sdv run`, the
# simulation, comes with the runtime; until then the demo stops at the validated IR.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
mkdir -p out
./build/release/sdv lint examples/cut_in.sdv
./build/release/sdv compile examples/cut_in.sdv -o out/cut_in.sdvir
