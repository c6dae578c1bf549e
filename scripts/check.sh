#!/usr/bin/env bash
# Install, build and run every test: the CI build (warnings as errors), then the same tests
# under AddressSanitizer + UndefinedBehaviorSanitizer. The last line is CTest's summary.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --tests
# playwright-core for the browser test of `sdv view` (from package-lock.json; needs the npm
# registry; without it that test fails with a message saying so).
npm ci --prefix tests/browser --no-audit --no-fund --loglevel=error || echo "warning: npm ci failed: the browser tests will fail"
jobs="$(nproc)"
cmake --preset ci >/dev/null
cmake --build --preset ci -j "$jobs"
ctest --preset ci -j "$jobs"
if [ "${SDV_SKIP_ASAN:-0}" != 1 ]; then
    cmake --preset asan >/dev/null
    cmake --build --preset asan -j "$jobs"
    ctest --preset asan -j "$jobs"
fi
