#!/usr/bin/env bash
# Regenerates the expected outputs of golden cases from the current build:
#   scripts/update-golden.sh [BUILD_DIR] [CASE_DIR...]   (default: build/dev, all cases)
# Review the diff before committing: a changed expectation is a changed behaviour.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/dev}
shift || true
cases=("$@")
if [ ${#cases[@]} -eq 0 ]; then
    mapfile -t cases < <(find tests/golden -mindepth 2 -maxdepth 2 -type d | sort)
fi
for c in "${cases[@]}"; do
    bash tests/golden/run_golden.sh "$PWD/$c" "$PWD/$build/sdv" --update
done
echo "updated ${#cases[@]} golden cases"
