#!/usr/bin/python3
"""Benchmark (not a test): the Linear Solver a deck gets when it names none (Direct Solver = Automatic,
core/LinearSolver.cpp) against explicit settings, on the loaded crossed layers of bench_scale.py
(`beamcontact generate grid --n n --m n --elements n+1 --gap 0 --press 0 --load P`, n^2 contact points), or
on the plain-weave mat (--model weave: `beamcontact generate weave --n n --m n --friction 0.2`).

Each round runs every (size, strategy, ranks, variant) once, in turn (a slow spell of the machine then
falls on every variant alike), and there are --repeat rounds. A variant is "default" (the deck has no
Linear Solver list), "KLU2", "UMFPACK" or "MUMPS", with "+reuse" for Reuse Factorization = true.
Per configuration it prints the medians of the load stepping's wall time (summary.csv solve_seconds)
and of the time per Newton iteration (the stages of timers.txt, as bench_scale.py), the Newton
iterations, the solver the default chose (from effective_parameters.xml), and the ratio of the
default's solve time to the best explicit variant's.

Usage: bench_default_solver.py BEAMCONTACT [--sizes 8,16,32] [--strategies Penalty,Lagrange Multiplier]
          [--ranks 1] [--variants default,KLU2,KLU2+reuse,UMFPACK+reuse] [--repeat 3] [--increments 5]
          [--work DIR] [--mpiexec mpirun]
"""
import argparse
import csv
import math
import os
import re
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_scale import SHORT, run_once  # noqa: E402


def linear_list(variant):
    if variant == "default":
        return ""
    method, _, reuse = variant.partition("+")
    return (f'<ParameterList name="Linear Solver"><Parameter name="Direct Solver" type="string" value="{method}"/>'
            f'<Parameter name="Reuse Factorization" type="bool" value="{"true" if reuse else "false"}"/>'
            '</ParameterList>')


def chosen(out):
    """The Direct Solver and Reuse Factorization written in effective_parameters.xml."""
    text = open(os.path.join(out, "effective_parameters.xml")).read()
    lin = text[text.find('name="Linear Solver"'):]
    method = re.search(r'name="Direct Solver" type="string" value="([^"]*)"', lin)
    reuse = re.search(r'name="Reuse Factorization" type="bool" value="([^"]*)"', lin)
    return (method.group(1) if method else "?") + ("+reuse" if reuse and reuse.group(1) == "true" else "")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("exe")
    ap.add_argument("--sizes", default="8,16,32")
    ap.add_argument("--strategies", default="Penalty,Lagrange Multiplier")
    ap.add_argument("--ranks", default="1")
    ap.add_argument("--variants", default="default,KLU2,KLU2+reuse,UMFPACK+reuse")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--increments", type=int, default=5)
    ap.add_argument("--model", default="grid", choices=["grid", "weave"],
                    help="grid: the loaded crossed layers; weave: generate weave --n n --m n (8 elements per spacing, "
                         "warp ends pulled, friction 0.2)")
    ap.add_argument("--work", default="bench_default_solver")
    ap.add_argument("--mpiexec", default="mpirun")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    sizes = [int(s) for s in a.sizes.split(",")]
    strategies = a.strategies.split(",")
    rank_counts = [int(r) for r in a.ranks.split(",")]
    variants = a.variants.split(",")
    configs = []
    for n in sizes:
        span = 10.0 * (n + 1)
        load = 0.1 * 384 * 1e5 * math.pi / 4 / (5 * n * span ** 3)
        base = os.path.join(a.work, f"{a.model}{n}.xml")
        options = (["--friction", "0", "--elements", str(n + 1), "--gap", "0", "--press", "0", "--load", repr(load)]
                   if a.model == "grid" else ["--friction", "0.2"])
        subprocess.run([a.exe, "generate", a.model, "--n", str(n), "--m", str(n), "--increments", str(a.increments),
                        "--overwrite", "--output", base] + options, check=True, capture_output=True)
        text = open(base).read()
        for strategy in strategies:
            for variant in variants:
                deck = os.path.join(a.work, f"{a.model}{n}_{SHORT.get(strategy, strategy)}_{variant.replace('+', '_')}.xml")
                t = text.replace('name="Type" type="string" value="Penalty"',
                                 f'name="Type" type="string" value="{strategy}"', 1)
                t = t.replace('<ParameterList name="BeamContact">',
                              '<ParameterList name="BeamContact"><ParameterList name="Output"><Parameter '
                              'name="Write VTK" type="bool" value="false"/></ParameterList>' + linear_list(variant), 1)
                with open(deck, "w") as f:
                    f.write(t)
                for ranks in rank_counts:
                    configs.append((n, strategy, ranks, variant, deck))
    runs = {c[:4]: [] for c in configs}
    for _ in range(a.repeat):
        for n, strategy, ranks, variant, deck in configs:
            out = deck[:-4] + f"_np{ranks}"
            r = run_once(a.exe, deck, out, ranks, a.mpiexec)
            with open(os.path.join(out, "summary.csv")) as f:
                r["solve"] = float(next(csv.DictReader(f))["solve_seconds"])
            r["chosen"] = chosen(out)
            runs[(n, strategy, ranks, variant)].append(r)
    print(f"{'n x n':>7} {'points':>6} {'dofs':>7} {'method':>6} {'ranks':>5} {'variant':>14} {'chosen':>14} | "
          f"{'solve s':>8} {'s/iter':>8} {'iters':>5} {'done':>4}")
    for n in sizes:
        for strategy in strategies:
            for ranks in rank_counts:
                med = {}
                for variant in variants:
                    rs = runs[(n, strategy, ranks, variant)]
                    med[variant] = statistics.median(r["solve"] for r in rs)
                    r0 = rs[0]
                    print(f"{n:>3} x {n:<3} {n * n:>6} {r0['dofs']:>7} {SHORT.get(strategy, strategy):>6} {ranks:>5} "
                          f"{variant:>14} {r0['chosen']:>14} | {med[variant]:8.3f} "
                          f"{statistics.median(r['stage']['total'] for r in rs):8.4f} {r0['iterations']:>5} "
                          f"{'yes' if all(r['complete'] for r in rs) else 'no':>4}", flush=True)
                explicit = [v for v in variants if v != "default"]
                if "default" in med and explicit:
                    best = min(explicit, key=lambda v: med[v])
                    print(f"    default / best explicit ({best}): {med['default'] / med[best]:.2f}")
                    if "KLU2" in med:
                        print(f"    KLU2 (the old default) / default: {med['KLU2'] / med['default']:.2f}")


if __name__ == "__main__":
    main()
