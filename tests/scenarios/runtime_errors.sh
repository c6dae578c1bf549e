#!/usr/bin/env bash
# Runtime errors (a vehicle starting off the road, an unreachable goal) name the .sdv location
# of the declaration, exit 1, and never crash.
set -u
sdv=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
cat > "$dir/off.sdv" <<'SDV'
import "std/drive.sdv"
junction x {
    control stop_signs
}
scenario s {
    road x
    vehicle car: sdv { start lane south.inn at 10 m  tree std.drive() }
    expect no_collision()
}
SDV
cat > "$dir/unreachable.sdv" <<'SDV'
import "std/drive.sdv"
road r {
    lanes 1 forward, 1 backward
    straight 200 m
}
scenario s {
    road r
    vehicle car: sdv { start lane 1 at 10 m  goal lane -1 at 50 m  tree std.drive() }
    expect no_collision()
}
SDV
check() {
    local out code
    out=$("$sdv" run "$dir/$1.sdv" -o "$dir/out" 2>&1)
    code=$?
    if [ $code -eq 1 ] && grep -qE "$2" <<<"$out"; then
        echo "ok   $1: $out"
    else
        echo "FAIL $1 (exit $code): $out"
        fail=1
    fi
}
check off "off.sdv:7:13: vehicle 'car' starts off the road: lane 'x.south.inn' does not exist"
check unreachable "unreachable.sdv:8:51: the goal of vehicle 'car' is unreachable"
exit $fail
