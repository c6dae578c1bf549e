#!/usr/bin/env bash
# Regenerates docs/img/report.png, the README's picture of an `sdv view` report: the cut-in
# example, run with a decision trace, opened in headless Chromium by the browser test (which
# leaves the report at t = 15 s with the ego selected). Needs a build and `npm ci --prefix
# tests/browser`.  Usage: scripts/screenshot-report.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/dev}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/sdv" run examples/cut_in.sdv -o "$tmp/run" --trace --view > /dev/null
node tests/browser/browser_test.mjs "$tmp/run/report.html" docs/img/report.png > /dev/null
echo "wrote docs/img/report.png"
