#!/usr/bin/env bash
# Every Python block of docs/cosim.md runs against a real sdv and ends cleanly, and the C block is
# examples/cosim/c_client.c verbatim (that file is built and run by capi/c_client): the documented
# clients cannot drift from the protocol or the API. A block that reads the file "port" is a TCP
# client in JSON; one that connects to /tmp/sdv.sock a Unix client in binary (its socket moved to
# a private path, its schema module generated with protoc); one that imports sdv uses the C API.
# Usage: cosim_doc_examples.sh SDV LIBSDV REPO_ROOT
set -u
sdv=$1 lib=$2 root=$3
# A sanitizer build's test environment preloads the sanitizer runtimes for a Python host of
# libsdv.so (sdv_foreign_host_test); sdv links its own, so only that host may get them.
host=(env ${LD_PRELOAD:+"LD_PRELOAD=$LD_PRELOAD"} ${ASAN_OPTIONS:+"ASAN_OPTIONS=$ASAN_OPTIONS"})
unset LD_PRELOAD ASAN_OPTIONS
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$root/docs/cosim.md" "$tmp" "$root/examples/cosim/c_client.c" <<'PY' || exit 1
import pathlib, re, sys
md, out, c_file = pathlib.Path(sys.argv[1]).read_text(), pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
blocks = re.findall(r"^```python\n(.*?)^```", md, re.S | re.M)
for i, b in enumerate(blocks):
    (out / f"example_{i + 1}.py").write_text(b)
c_blocks = re.findall(r"^```c\n(.*?)^```", md, re.S | re.M)
if c_blocks != [c_file.read_text()]:
    sys.exit("FAIL: the C block of docs/cosim.md is not examples/cosim/c_client.c")
print(f"{len(blocks)} Python examples; the C example is examples/cosim/c_client.c")
PY
py_binary=/usr/bin/python3
"$py_binary" -c 'import google.protobuf' 2>/dev/null || py_binary=python3
fail=0
for f in "$tmp"/example_*.py; do
    name=$(basename "$f" .py)
    work=$tmp/$name
    mkdir -p "$work"
    cp "$f" "$work/example.py"  # beside the modules it imports
    f=$work/example.py
    server=""
    if grep -q 'open("port")' "$f"; then
        "$sdv" run "$root/tests/cli/data/cosim_highway.sdv" --cosim tcp://127.0.0.1:0 --cosim-port-file "$work/port" \
            --cosim-encoding json --cosim-step-timeout 30 -o "$work/out" > "$work/sdv.log" 2>&1 &
        server=$!
        (cd "$work" && timeout 300 python3 "$f") > "$work/client.log" 2>&1
    elif grep -q '/tmp/sdv.sock' "$f"; then
        sed -i "s|/tmp/sdv.sock|$work/sdv.sock|" "$f"
        protoc -I "$root/runtime/cosim" --python_out="$work" "$root/runtime/cosim/sdv_cosim.proto"
        "$sdv" run "$root/tests/cli/data/cosim_highway.sdv" --cosim "unix:$work/sdv.sock" --cosim-step-timeout 30 \
            -o "$work/out" > "$work/sdv.log" 2>&1 &
        server=$!
        (cd "$work" && timeout 300 "$py_binary" "$f") > "$work/client.log" 2>&1
    elif grep -q '^import sdv' "$f"; then
        (cd "$root" && SDV_LIBRARY=$lib timeout 300 "${host[@]}" python3 "$f") > "$work/client.log" 2>&1
    else
        echo "FAIL: $name: no known way to run it"
        fail=1
        continue
    fi
    code=$?
    if [ -n "$server" ]; then
        wait "$server"
        scode=$?
        [ "$scode" = 0 ] || { echo "FAIL: $name: sdv exited $scode"; cat "$work/sdv.log"; fail=1; }
    fi
    if [ "$code" != 0 ]; then
        echo "FAIL: $name: the client exited $code"
        cat "$work/client.log"
        fail=1
    else
        echo "ok $name: $(tail -1 "$work/client.log")"
    fi
done
rm -rf "$root/out/python"  # the Python section's example writes there
exit $fail
