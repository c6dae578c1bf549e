#!/usr/bin/env bash
# Runs one golden case: `run_golden.sh CASE_DIR SDV [--update]`. Compares stdout, stderr and
# the exit code with the case's expected.* files (or writes them with --update).
set -u
case_dir=$1
sdv=$2
update=${3:-}
verb=$(basename "$(dirname "$case_dir")")
cd "$case_dir" || exit 2
if [ -f args ]; then
    read -r -a argv < args
else
    argv=("$verb" input.sdv)
fi
out=$(mktemp) err=$(mktemp)
trap 'rm -f "$out" "$err"' EXIT
timeout 60 "$sdv" "${argv[@]}" >"$out" 2>"$err"
code=$?
if [ "$update" = --update ]; then
    cp "$out" expected.out
    cp "$err" expected.err
    echo "$code" > expected.exit
    for f in expected.out expected.err; do [ -s "$f" ] || rm -f "$f"; done
    exit 0
fi
status=0
expected_code=$(cat expected.exit 2>/dev/null || echo 0)
if [ "$code" != "$expected_code" ]; then
    echo "exit code $code, expected $expected_code"
    status=1
fi
for stream in out err; do
    want=expected.$stream
    got=$out
    [ "$stream" = err ] && got=$err
    if [ -f "$want" ]; then
        if ! diff -u "$want" "$got"; then status=1; fi
    elif [ -s "$got" ]; then
        echo "unexpected std$stream:"
        cat "$got"
        status=1
    fi
done
exit $status
