#!/usr/bin/env bash
# Install, build and run every test: the CI build (warnings as errors), the fuzz stage (every
# libFuzzer target over its seeds plus a fixed number of new inputs), then the same tests under
# AddressSanitizer + UndefinedBehaviorSanitizer (clang, in the fuzz stage's build; the gcc
# sanitizer build is the asan preset). The last line is CTest's summary.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage prints its seconds ("stage NAME: N s"); the last, CTest under ASan+UBSan, its own.
bash scripts/install-deps.sh --tests
# playwright-core for the browser test of `sdv view` (from package-lock.json; needs the npm
# registry; without it that test fails with a message saying so).
npm ci --prefix tests/browser --no-audit --no-fund --loglevel=error || echo "warning: npm ci failed: the browser tests will fail"
jobs="$(nproc)"
# On a machine with pyenv (the CI machine's image has it), python3 on PATH is a shim: 2.5 s to
# start `python3 -c pass` on a busy machine, against 0.3 s for the interpreter it resolves to. The
# tests and the fuzz corpus start python3 hundreds of times, so that interpreter goes first on PATH.
if py=$(pyenv which python3 2>/dev/null); then
    export PATH="$(dirname "$py"):$PATH"
fi
cmake --preset ci >/dev/null
stage_start=$SECONDS
cmake --build --preset ci -j "$jobs"
echo "stage ci build: $((SECONDS - stage_start)) s"
stage_start=$SECONDS
ctest --preset ci -j "$jobs"
echo "stage ci tests: $((SECONDS - stage_start)) s"
# The sanitizer build (the fuzz preset: clang, ASan+UBSan, libFuzzer's coverage in every
# library) builds the libFuzzer targets and every test once, for both stages below.
cmake --preset fuzz >/dev/null
stage_start=$SECONDS
cmake --build --preset fuzz -j "$jobs" >build/fuzz-build.log 2>&1 ||
    { tail -40 build/fuzz-build.log; echo "building the sanitizer build (fuzz preset) failed"; exit 1; }
echo "stage sanitizer build: $((SECONDS - stage_start)) s"
# Fuzz stage (tests/fuzz/README.md): every libFuzzer target over its seed corpus plus a fixed
# number of new inputs, two targets at a time; a crash, a leak, undefined behaviour, an input
# over 1 s or 2 GB fails CI. Count bounded, never time bounded: the same inputs on every run.
# Each target's log is in build/fuzz/ci-logs/.
if [ "${SDV_SKIP_FUZZ:-0}" != 1 ]; then
    fuzz_start=$SECONDS
    scripts/fuzz-corpus.sh build/ci build/fuzz/corpus-ci >/dev/null
    rm -rf build/fuzz/ci-logs && mkdir -p build/fuzz/ci-logs
    fuzz_targets=(sdv_frontend ir_reader btree gss_scenario lanelet2 cosim_frame sweep_results recording run_dir run_diff
                  sweep_rows)
    fuzz_ok=1
    printf '%s\n' "${fuzz_targets[@]}" | xargs -P "$jobs" -I{} sh -c \
        'scripts/fuzz.sh {} --ci --corpus build/fuzz/corpus-ci > build/fuzz/ci-logs/{}.log 2>&1' || fuzz_ok=0
    grep -h "^fuzz.sh: fuzz_.*executions" build/fuzz/ci-logs/*.log || true
    echo "stage fuzz: $((SECONDS - fuzz_start)) s"
    if [ $fuzz_ok = 0 ]; then
        grep -h -E "FINDING|ERROR|runtime error|sdv fuzz:|ALARM|failed|^    /" build/fuzz/ci-logs/*.log | head -40
        echo "fuzz stage failed (logs: build/fuzz/ci-logs; replay a finding: build/fuzz/fuzz/fuzz_TARGET FILE)"
        exit 1
    fi
fi
# Every test again under ASan+UBSan, in the same build.
if [ "${SDV_SKIP_ASAN:-0}" != 1 ]; then
    ctest --preset fuzz -j "$jobs"
fi
