#!/usr/bin/env bash
# Browser test of `sdv view` (issue: see a run): runs an example with a decision trace, writes
# its report with `sdv run --view`, opens it in Debian's headless Chromium through
# playwright-core (tests/browser/node_modules, installed by `npm ci --prefix tests/browser`,
# which scripts/check.sh runs) and drives the real UI. The screenshot is kept as an artefact.
# Usage: run_view_test.sh SDV EXAMPLE.sdv ARTEFACT_DIR [--require=pedestrian,crosswalk,walkway]
# A scenario may name files of the shared data folder as @SDV_SHARED_DIR@ ($SDV_SHARED_DIR).
set -u
sdv=$1 example=$2 artefacts=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
if [ ! -d "$here/node_modules/playwright-core" ]; then
    echo "FAIL: playwright-core is not installed: run 'npm ci --prefix tests/browser' (needs the npm registry)"
    exit 1
fi
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ]; then
    echo "FAIL: no Chromium at ${CHROMIUM:-/usr/bin/chromium}: install Debian's chromium (scripts/install-deps.sh does)"
    exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
name=$(basename "$example" .sdv)
if grep -q '@SDV_SHARED_DIR@' "$example"; then
    if [ ! -d "${SDV_SHARED_DIR:-}" ]; then
        echo "FAIL: $example needs SDV_SHARED_DIR (the shared data folder)"
        exit 1
    fi
    sed "s#@SDV_SHARED_DIR@#$SDV_SHARED_DIR#g" "$example" > "$tmp/$name.sdv"
    example=$tmp/$name.sdv
fi
"$sdv" run "$example" -o "$tmp/run" --trace --view > "$tmp/run.log" 2>&1 || { cat "$tmp/run.log"; exit 1; }
mkdir -p "$artefacts"
node "$here/browser_test.mjs" "$tmp/run/report.html" "$artefacts/view_$name.png" "$@"
