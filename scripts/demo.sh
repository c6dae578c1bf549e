#!/usr/bin/env bash
# Newcomer's first command: install, build (release) and run the headline example, the
# paper's cut-in case study on a built-in road: the summary on stdout, the outputs in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
mkdir -p out
./build/release/sdv lint examples/cut_in.sdv
./build/release/sdv run examples/cut_in.sdv -o out/cut_in
