#!/usr/bin/env bash
# Every example and every standard-library file lints with exit 0 and no output at all
# (no warnings either, promoted with -Werror).
set -u
sdv=$1
root=$2
fail=0
while IFS= read -r f; do
    out=$("$sdv" lint -Werror "$f" 2>&1)
    code=$?
    if [ $code -ne 0 ] || [ -n "$out" ]; then
        echo "FAIL $f (exit $code)"
        echo "$out"
        fail=1
    else
        echo "ok   $f"
    fi
done < <(find "$root/examples" "$root/stdlib-trees" -name '*.sdv' | sort)
exit $fail
