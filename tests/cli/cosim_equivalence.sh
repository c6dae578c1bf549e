#!/usr/bin/env bash
# Co-simulation equivalence (issue 15, COSIM.md §3.d): the reference client
# (examples/cosim/ads_client.py) drives the ego of examples/cosim/cut_in.sdv (a) in process
# through the C API, (b) over TCP in the binary encoding, (c) over a Unix socket in JSON with two
# planning threads; all three write byte-identical trajectories.csv, summary.json and road.json,
# the client's run passes its expectations (exit 0), and replaying the recording of (b) without the client
# reproduces every reply and the same outputs. Every wait is bounded by --cosim-step-timeout.
# Usage: cosim_equivalence.sh SDV LIBSDV REPO_ROOT
set -u
sdv=$1 lib=$2 root=$3
# A sanitizer build's test environment preloads the sanitizer runtimes for a Python host of
# libsdv.so (sdv_foreign_host_test); sdv links its own, so only that host may get them.
host=(env ${LD_PRELOAD:+"LD_PRELOAD=$LD_PRELOAD"} ${ASAN_OPTIONS:+"ASAN_OPTIONS=$ASAN_OPTIONS"})
unset LD_PRELOAD ASAN_OPTIONS
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scenario=$root/examples/cosim/cut_in.sdv
client=$root/examples/cosim/ads_client.py
fail=0
serve() {  # serve NAME ENDPOINT ENCODING [extra...]: sdv in the background, its pid in $pid
    local name=$1 endpoint=$2 encoding=$3
    shift 3
    "$sdv" run "$scenario" --cosim "$endpoint" --cosim-port-file "$tmp/$name.port" --cosim-encoding "$encoding" \
        --cosim-step-timeout 60 --cosim-connect-timeout 60 -o "$tmp/$name" "$@" > "$tmp/$name.log" 2>&1 &
    pid=$!
}
finish() {  # finish NAME: waits for sdv, which must exit 0
    local name=$1
    wait "$pid"
    local code=$?
    if [ "$code" != 0 ]; then
        echo "FAIL: $name: sdv exited $code"
        cat "$tmp/$name.log"
        fail=1
    fi
}
# The binary client needs python3-protobuf (Debian's, for /usr/bin/python3).
py_binary=/usr/bin/python3
"$py_binary" -c 'import google.protobuf' 2>/dev/null || py_binary=python3

SDV_LIBRARY=$lib "${host[@]}" python3 "$client" --in-process "$scenario" -o "$tmp/inproc" || { echo "FAIL: in process"; fail=1; }

serve tcpbin tcp://127.0.0.1:0 binary --cosim-record "$tmp/session.cosim"
"$py_binary" "$client" --port-file "$tmp/tcpbin.port" --encoding binary || { echo "FAIL: TCP binary client"; fail=1; }
finish tcpbin

serve unixjson "unix:$tmp/s.sock" json --threads 2
python3 "$client" --port-file "$tmp/unixjson.port" --encoding json || { echo "FAIL: Unix JSON client"; fail=1; }
finish unixjson

"$sdv" replay-cosim "$tmp/session.cosim" -o "$tmp/replay" > "$tmp/replay.log" 2>&1 || { echo "FAIL: replay"; cat "$tmp/replay.log"; fail=1; }

for f in trajectories.csv summary.json road.json; do
    for run in tcpbin unixjson replay; do
        if ! cmp -s "$tmp/inproc/$f" "$tmp/$run/$f"; then
            echo "FAIL: $f of $run differs from the in-process run"
            diff <(head -c 2000 "$tmp/inproc/$f") <(head -c 2000 "$tmp/$run/$f") | head -10
            fail=1
        fi
    done
done
grep -q '"passed": true' "$tmp/inproc/summary.json" || { echo "FAIL: the reference client's run failed its expectations"; fail=1; }
[ $fail -eq 0 ] && echo "in process, TCP binary, Unix JSON and the replay: byte-identical outputs; the client's run passes"
exit $fail
