#!/usr/bin/python3
"""Benchmark of the seed paper's examples: each example deck with each strategy, run REPEAT times
one after the other on one core (one MPI rank), reporting the median solve time (wall time of the
load stepping, from the run's summary.csv), Newton iterations, passes and peak memory, and the ratios
Lagrange / penalty and augmented Lagrange / penalty of the median solve times.

    /usr/bin/python3 bench/bench_examples.py BEAMCONTACT [--repeat N] [--work DIR] [--automatic]

Penalty runs use the decks' penalty parameters (eps_N = 1e4, eps_T = 400); with --automatic, Penalty
and Augmented Lagrange choose theirs per point ("Automatic"). The last table also gives the ratios of
the Newton iterations (deterministic), augmented Lagrange / penalty (docs/contact.md, "Cost of the
augmentations"). The paper's figures on a
900 MHz PC (Lagrange / penalty): Example 1 87 s / 37 s, Example 2 36 / 24, Example 3 50 / 35.
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent
STRATEGIES = ["Penalty", "Lagrange Multiplier", "Augmented Lagrange"]
PAPER = {"example1": (37, 87), "example2": (24, 36), "example3": (35, 50)}


def run_once(exe, deck_text, work):
    deck = work / "deck.xml"
    deck.write_text(deck_text)
    out = work / "out"
    r = subprocess.run([exe, "run", str(deck), "--output", str(out), "--quiet"], capture_output=True, text=True,
                       env={**os.environ, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"})
    if r.returncode != 0:
        return None
    with open(out / "summary.csv") as f:
        return next(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("beamcontact")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--work", default=None)
    ap.add_argument("--automatic", action="store_true", help="Automatic penalty parameters")
    a = ap.parse_args()
    work = Path(a.work or tempfile.mkdtemp(prefix="bench_examples_"))
    work.mkdir(parents=True, exist_ok=True)
    print(f"examples benchmark ({'Automatic' if a.automatic else 'deck'} penalty parameters): {a.repeat} runs each, one rank, medians (solve = load stepping wall time)")
    print(f"{'example':9} {'strategy':20} {'solve [s]':>10} {'min':>7} {'max':>7} {'Newton':>7} {'max/step':>8} "
          f"{'passes':>7} {'steps':>6} {'peak MB':>8} {'ms/Newton':>9}")
    medians = {}
    newtons = {}
    for ex in ["example1", "example2", "example3"]:
        base = (HERE / "input" / f"{ex}.xml").read_text()
        for s in STRATEGIES:
            text = re.sub(r'<Parameter name="Type" type="string" value="[^"]*"/>',
                          f'<Parameter name="Type" type="string" value="{s}"/>', base)
            if a.automatic:
                text = re.sub(r'<Parameter name="(Normal|Tangential) Penalty Parameter" type="double" value="[^"]*"/>',
                              r'<Parameter name="\1 Penalty Parameter" type="string" value="Automatic"/>', text)
            text = text.replace('<ParameterList name="Output">',
                                '<ParameterList name="Output"><Parameter name="Write VTK" type="bool" value="false"/>', 1)
            runs = [run_once(a.beamcontact, text, work) for _ in range(a.repeat)]
            if any(r is None for r in runs):
                print(f"{ex:9} {s:20} did not complete")
                continue
            t = [float(r["solve_seconds"]) for r in runs]
            r0 = runs[0]
            med = statistics.median(t)
            medians[(ex, s)] = med
            newton = int(r0["newton_iterations"])
            newtons[(ex, s)] = newton
            print(f"{ex:9} {s:20} {med:10.3f} {min(t):7.3f} {max(t):7.3f} {newton:7d} {r0['max_newton_per_step']:>8} "
                  f"{r0['passes']:>7} {r0['steps']:>6} {float(r0['peak_memory_mb']):8.1f} {1000 * med / newton:9.2f}")
    print()
    print(f"{'example':9} {'Lagrange/penalty':>17} {'augmented/penalty':>18} {'paper Lagrange/penalty':>23} "
          f"{'Newton augmented/penalty':>25}")
    for ex in ["example1", "example2", "example3"]:
        p = medians.get((ex, "Penalty"))
        lm = medians.get((ex, "Lagrange Multiplier"))
        al = medians.get((ex, "Augmented Lagrange"))
        fmt = lambda x: f"{x / p:.2f}" if (x and p) else "-"
        np_, na = newtons.get((ex, "Penalty")), newtons.get((ex, "Augmented Lagrange"))
        nr = f"{na / np_:.2f}" if (np_ and na) else "-"
        print(f"{ex:9} {fmt(lm):>17} {fmt(al):>18} {PAPER[ex][1] / PAPER[ex][0]:23.2f} {nr:>25}")


if __name__ == "__main__":
    sys.exit(main())
