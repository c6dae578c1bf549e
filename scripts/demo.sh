#!/usr/bin/env bash
# Newcomer's first command: install, build (release) and run the headline example.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
./build/release/sdv run examples/cut_in.sdv -o out/cut_in
