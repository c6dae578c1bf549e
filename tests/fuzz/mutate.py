#!/usr/bin/env python3
"""Seeded mutation fuzzing: mutate.py SDV ROOT N. For every example and stdlib file, N mutants
(byte flips, deletions, duplications, token swaps, truncations, deep nesting) go through `sdv lint`;
for the IR of each example, N mutants go through `sdv check-ir`. Any exit code other than 0/1, or
a time-out, is a failure. Deterministic (fixed seed), so a failure reproduces; the mutants run on
every core."""
import concurrent.futures
import os
import pathlib
import random
import shutil
import subprocess
import sys
import tempfile

sdv, root, n = sys.argv[1], pathlib.Path(sys.argv[2]), int(sys.argv[3])
rng = random.Random(20261122)
TOKENS = [b"{", b"}", b"(", b")", b",", b"=", b"m/s", b"\xc2\xb1", b"samples", b"..", b"tree", b"maneuver",
          b"1e308", b"-", b"\"", b"#", b"\x00", b"\xff", b"lane", b"subtree", b"not not", b"%"]


def mutate(data: bytes) -> bytes:
    b = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        op = rng.randrange(6)
        if not b:
            b += rng.choice(TOKENS)
            continue
        i = rng.randrange(len(b))
        if op == 0:
            b[i] = rng.randrange(256)
        elif op == 1:
            del b[i:i + rng.randint(1, 20)]
        elif op == 2:
            j = rng.randrange(len(b))
            b[i:i] = b[j:j + rng.randint(1, 40)]
        elif op == 3:
            b[i:i] = rng.choice(TOKENS)
        elif op == 4:
            b = b[:i]
        else:
            b[i:i] = b"sequence {" * rng.randint(1, 300)
    return bytes(b)


def run(args, path):
    try:
        p = subprocess.run([sdv] + args + [path], capture_output=True, timeout=30)
    except subprocess.TimeoutExpired:
        return "timeout"
    return None if p.returncode in (0, 1) else f"exit {p.returncode}: {p.stderr.decode(errors='replace')[-300:]}"


def check(job):
    """Runs one mutant; returns its failure message or None."""
    label, args, path, keep = job
    err = run(args, str(path))
    if not err:
        return None
    if keep:
        shutil.copyfile(path, tmp.parent / keep)
        return f"{label} ({tmp.parent / keep}): {err}"
    return f"{label}: {err}"


# The mutants are drawn in one fixed order from one seeded generator and written to files of
# their own, then run on every core; failures are reported in that order, so a run is the same
# whatever the number of cores.
with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    jobs = []
    sources = sorted((root / "examples").glob("*.sdv")) + sorted((root / "stdlib-trees").glob("*.sdv"))
    for src in sources:
        data = src.read_bytes()
        for k in range(n):
            m = tmp / f"m_{src.stem}_{k}.sdv"
            m.write_bytes(mutate(data))
            jobs.append((f"lint {src.name} mutant {k}", ["lint"], m, f"sdv_fuzz_{src.stem}_{k}.sdv"))
    for src in sorted((root / "examples").glob("*.sdv")):
        ir = tmp / f"{src.stem}.sdvir"
        subprocess.run([sdv, "compile", str(src), "-o", str(ir)], capture_output=True, check=True)
        data = ir.read_bytes()
        for k in range(n):
            m = tmp / f"m_{src.stem}_{k}.sdvir"
            m.write_bytes(mutate(data))
            jobs.append((f"check-ir {src.name} mutant {k}", ["check-ir"], m, None))
    # GeoScenario inputs: every .btree of the reference's library (mutated in a copy of the
    # library, so that subtrees resolve; a copy per mutant) and every scenario.
    gss = root.resolve().parent / "shared" / "data" / "geoscenario"
    if gss.is_dir():
        lib = tmp / "btrees"
        lib.mkdir()
        originals = {p.name: p.read_bytes() for p in sorted((gss / "btrees" / "sdv").glob("*.btree"))}
        for name, data in originals.items():
            (lib / name).write_bytes(data)
        deep = b"".join(b"    " * d + b"?\n" for d in range(1, 200))
        for name, data in originals.items():
            for k in range(max(1, n // 3)):
                mutant = mutate(data) if k % 10 else data + deep
                copy = tmp / f"btrees_{name}_{k}"
                shutil.copytree(lib, copy)
                (copy / name).write_bytes(mutant)
                jobs.append((f"lint {name} mutant {k}", ["lint"], copy / name, f"sdv_fuzz_{k}_{name}"))
        for src in sorted((gss / "scenarios").glob("*.osm")):
            data = src.read_bytes()
            for k in range(max(1, n // 10)):
                d = tmp / f"osm_{src.stem}_{k}"
                d.mkdir()
                (d / src.name).write_bytes(mutate(data))
                jobs.append((f"lint {src.name} mutant {k}", ["lint", "--btree-path", str(lib), "--map-dir", str(gss)],
                             d / src.name, f"sdv_fuzz_{k}_{src.name}"))
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        failures = [f for f in pool.map(check, jobs) if f]
    count = len(jobs)
print(f"{count} mutants, {len(failures)} failures")
for f in failures[:20]:
    print("FAIL", f)
sys.exit(1 if failures else 0)
