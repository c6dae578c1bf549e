#!/usr/bin/env bash
# `sdv compile` is deterministic (twice → byte-identical IR) and the IR reader rejects
# corrupted files (flipped byte, truncation, wrong version) with a clear message and exit 1.
set -u
sdv=$1
root=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
note() { echo "$1"; }
bad() { echo "FAIL $1"; fail=1; }

for f in "$root"/examples/*.sdv; do
    name=$(basename "$f" .sdv)
    "$sdv" compile "$f" -o "$dir/$name.a.sdvir" >/dev/null || { bad "compile $f"; continue; }
    "$sdv" compile "$f" -o "$dir/$name.b.sdvir" >/dev/null || { bad "compile $f"; continue; }
    if cmp -s "$dir/$name.a.sdvir" "$dir/$name.b.sdvir"; then note "ok   deterministic $name"; else bad "IR differs between two compiles of $name"; fi
    "$sdv" check-ir "$dir/$name.a.sdvir" >/dev/null || bad "check-ir rejects a fresh IR of $name"
done

ir=$(ls "$dir"/*.a.sdvir | head -1)
size=$(stat -c %s "$ir")
expect_reject() {  # expect_reject NAME FILE PATTERN
    local err
    err=$("$sdv" check-ir "$2" 2>&1 >/dev/null)
    local code=$?
    if [ $code -eq 1 ] && grep -qiE "$3" <<<"$err"; then
        note "ok   rejects $1: $err"
    else
        bad "$1: exit $code, message: $err"
    fi
}
# A flipped byte in the middle of the program (a digit changed keeps the JSON valid).
python3 - "$ir" "$dir/flipped.sdvir" <<'PY'
import sys, re
data = open(sys.argv[1], "rb").read()
m = [x.start() for x in re.finditer(rb"[0-9]", data)]
i = m[len(m) // 2]
data = data[:i] + (b"7" if data[i:i+1] != b"7" else b"3") + data[i+1:]
open(sys.argv[2], "wb").write(data)
PY
expect_reject "flipped byte" "$dir/flipped.sdvir" "corrupt|hash"
head -c $((size / 2)) "$ir" > "$dir/truncated.sdvir"
expect_reject "truncated file" "$dir/truncated.sdvir" "invalid|truncat|JSON"
sed 's/"version": *1/"version": 7/' "$ir" > "$dir/version.sdvir"
expect_reject "wrong version" "$dir/version.sdvir" "version"
: > "$dir/empty.sdvir"
expect_reject "empty file" "$dir/empty.sdvir" "invalid|empty|JSON"
head -c 2000 /dev/urandom > "$dir/garbage.sdvir"
expect_reject "garbage" "$dir/garbage.sdvir" "invalid|JSON|not an sdv"
exit $fail
