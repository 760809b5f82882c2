#!/usr/bin/python3
"""Benchmark (not a test): what starting a run costs. Runs `beamcontact run DECK --quiet` (VTK as the deck
says) --repeat times per configuration, the configurations interleaved, and prints the medians of the
whole process's wall time (fork to exit, as the shell sees it), of the load stepping's wall time
(summary.csv solve_seconds) and of their ratio.

Configurations: the singleton start as beamcontact makes it (no Open MPI daemon), the same binary
with OMPI_MCA_ess_singleton_isolated=0 in the environment (the daemon forked, as before), and any
--other binaries (e.g. an older build) as they start by default.

Usage: bench_startup.py BEAMCONTACT [--deck input/example1.xml] [--repeat 5] [--other EXE ...] [--work DIR]
"""
import argparse
import csv
import os
import statistics
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def once(exe, deck, out, env):
    t0 = time.perf_counter()
    r = subprocess.run([exe, "run", deck, "--output", out, "--quiet", "--overwrite"], env=env, capture_output=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise SystemExit(f"bench_startup: {exe} exited with {r.returncode}: {r.stderr.decode()}")
    with open(os.path.join(out, "summary.csv")) as f:
        solve = float(next(csv.DictReader(f))["solve_seconds"])
    return wall, solve


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("exe")
    ap.add_argument("--deck", default=os.path.join(HERE, "..", "input", "example1.xml"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--other", action="append", default=[])
    ap.add_argument("--work", default="bench_startup")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    base = {k: v for k, v in os.environ.items()
            if not k.startswith(("OMPI_COMM_WORLD_", "PMIX_", "PMI_", "OMPI_MCA_ess_singleton"))}
    configs = [("no daemon (default)", a.exe, base),
               ("daemon (OMPI_MCA_ess_singleton_isolated=0)", a.exe, dict(base, OMPI_MCA_ess_singleton_isolated="0"))]
    configs += [(f"other: {exe}", exe, base) for exe in a.other]
    times = {name: [] for name, _, _ in configs}
    for _ in range(a.repeat):
        for i, (name, exe, env) in enumerate(configs):
            times[name].append(once(exe, a.deck, os.path.join(a.work, f"run{i}"), env))
    print(f"{os.path.basename(a.deck)}, medians of {a.repeat}:")
    print(f"{'configuration':45s} {'process s':>9} {'solve s':>8} {'process/solve':>13}")
    for name, _, _ in configs:
        t = times[name]
        wall, solve = statistics.median(w for w, _ in t), statistics.median(s for _, s in t)
        ratio = statistics.median(w / s for w, s in t)
        print(f"{name:45s} {wall:9.3f} {solve:8.3f} {ratio:13.2f}")


if __name__ == "__main__":
    main()
