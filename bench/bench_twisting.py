#!/usr/bin/python3
"""The twisting-rods table (not a test; tests/regression/test_twisting_rods.cpp runs its corners):
rods of 16, 32, 64 elements (rod 2 one fewer) twisted by theta = pi in 10, 20, 50 increments, with
each strategy, against the helix closed form on the middle quarter (bench/twisting_results.py).
Prints one row per run: exit, T reached, Newton iterations, mid-node phase error, line-load error,
mean gap there against its reference, the deepest gap anywhere, the middle's pitch against a
uniform twist and the ends' boundary layer (measured, and sqrt(EI / N)), and the wall time.
Usage: bench_twisting.py BEAMCONTACT [--work DIR] [--jobs N] [--elements 16 32 64]
       [--increments 10 20 50] [--types Penalty ...] [--eps 1e4]"""
import argparse
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import twisting_deck as td  # noqa: E402
import twisting_results as tr  # noqa: E402

SHORT = {"Penalty": "P", "Lagrange Multiplier": "LM", "Augmented Lagrange": "AL"}


def run(exe, work, n, inc, typ, eps, timeout):
    name = f"{SHORT.get(typ, typ)}_{n}_{inc}"
    path = os.path.join(work, name + ".xml")
    with open(path, "w") as f:
        f.write(td.deck(n, inc, typ, eps).replace(
            '<ParameterList name="Output">', '<ParameterList name="Output">\n    <Parameter name="Write VTK" type="bool" value="false"/>'))
    out = os.path.join(work, name)
    start = time.time()
    try:
        subprocess.run([exe, "run", path, "--output", out, "--overwrite"], stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL, timeout=timeout)
    except subprocess.TimeoutExpired:
        return name, None, time.time() - start
    try:
        return name, tr.read(out, eps if typ == "Penalty" else None), time.time() - start
    except Exception as e:  # a run that stopped before its first step
        return name, {"status": f"unreadable ({e})"}, time.time() - start


def main():
    a = argparse.ArgumentParser()
    a.add_argument("exe")
    a.add_argument("--work", default="bench_twisting")
    a.add_argument("--jobs", type=int, default=1)
    a.add_argument("--elements", type=int, nargs="+", default=[16, 32, 64])
    a.add_argument("--increments", type=int, nargs="+", default=[10, 20, 50])
    a.add_argument("--types", nargs="+", default=["Penalty", "Lagrange Multiplier", "Augmented Lagrange"])
    a.add_argument("--eps", type=float, default=td.EPS_N)
    a.add_argument("--timeout", type=float, default=1800)
    o = a.parse_args()
    os.makedirs(o.work, exist_ok=True)
    cases = [(n, i, t) for t in o.types for n in o.elements for i in o.increments]
    print(f"{'case':12s} {'exit':10s} {'T':>5s} {'Newton':>6s} {'phase':>9s} {'load err':>9s} {'gap':>10s} "
          f"{'gap ref':>10s} {'gap min':>10s} {'pitch':>7s} {'layer':>6s} {'sqrt(EI/N)':>10s} {'time':>6s}", flush=True)
    with ThreadPoolExecutor(o.jobs) as pool:
        for name, r, secs in pool.map(lambda c: run(o.exe, o.work, *c, o.eps, o.timeout), cases):
            if r is None:
                print(f"{name:12s} timeout after {secs:.0f} s", flush=True)
                continue
            if "load_err" not in r:
                print(f"{name:12s} {r['status']:10s} {r.get('T', 0):5.3g} {r.get('newton', 0):6d}", flush=True)
                continue
            print(f"{name:12s} {r['status']:10s} {r['T']:5.3g} {r['newton']:6d} {r['phase_err']:9.1e} "
                  f"{r['load_err']:9.1e} {r['gap']:10.3e} {r['gap_ref']:10.3e} {r['gap_min']:10.3e} "
                  f"{r['pitch_ratio']:7.4f} {r['layer']:6.3f} {r['layer_ref']:10.3f} {secs:6.0f}", flush=True)


if __name__ == "__main__":
    main()
