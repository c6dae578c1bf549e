#!/usr/bin/env bash
# Every ```sdv block in the docs is a complete file that lints clean (-Werror): the examples
# in the documentation cannot drift from the compiler.
set -u
sdv=$1
root=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$root/docs" "$dir" <<'PY'
import pathlib, re, sys
docs, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
n = 0
for md in sorted(docs.glob("*.md")):
    for i, block in enumerate(re.findall(r"^```sdv\n(.*?)^```", md.read_text(), re.S | re.M)):
        (out / f"{md.stem}_{i + 1}.sdv").write_text(block)
        n += 1
print(f"{n} examples extracted")
PY
fail=0
for f in "$dir"/*.sdv; do
    [ -e "$f" ] || continue
    out=$("$sdv" lint -Werror "$f" 2>&1)
    if [ $? -ne 0 ] || [ -n "$out" ]; then
        echo "FAIL $(basename "$f"):"
        echo "$out"
        fail=1
    else
        echo "ok   $(basename "$f")"
    fi
done
exit $fail
