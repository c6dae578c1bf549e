#!/usr/bin/env bash
# Browser test of the sweep report (issue 16, test campaigns): copies a sweep directory (or
# generates a synthetic one) into a temporary directory, writes its report there with
# `SDV view SWEEP_DIR -o SWEEP_DIR/report.html` (the report's links to runs/<i>/view.html are
# relative, so it must sit in the sweep directory), opens it in Debian's headless Chromium
# through playwright-core (tests/browser/node_modules, `npm ci --prefix tests/browser`) and
# drives the real UI with sweep_report_test.mjs. The screenshot is kept as an artefact.
#
# Usage: run_sweep_report_test.sh SDV SWEEP_DIR ARTEFACT_DIR
#   SWEEP_DIR  a sweep directory (results.csv, summary.json, runs/), or generated:KIND:N for a
#              synthetic one (KIND grid2, random2, latin3 or line1; see sweep_report_test.mjs)
set -u
sdv=$1 sweep=$2 artefacts=$3
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
case "$sweep" in
    generated:*)
        IFS=: read -r _ kind n <<< "$sweep"
        name="generated_${kind}_$n"
        node "$here/sweep_report_test.mjs" --generate "$kind" "$n" "$tmp/$name" || exit 1
        ;;
    *)
        if [ ! -f "$sweep/results.csv" ] || [ ! -f "$sweep/summary.json" ]; then
            echo "FAIL: $sweep is not a sweep directory (it needs results.csv and summary.json)"
            exit 1
        fi
        name=$(basename "$sweep")
        cp -r "$sweep" "$tmp/$name"
        ;;
esac
"$sdv" view "$tmp/$name" -o "$tmp/$name/report.html" > "$tmp/view.log" 2>&1 || { cat "$tmp/view.log"; exit 1; }
mkdir -p "$artefacts"
node "$here/sweep_report_test.mjs" "$tmp/$name/report.html" "$artefacts/sweep_report_$name.png"
