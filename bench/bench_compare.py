#!/usr/bin/env python3
"""Side-by-side timing of decks and rank counts, runs interleaved.

    bench_compare.py EXE --decks a.xml,b.xml --ranks 1,2 [--repeat 3] [--work DIR]

Each round runs every (deck, ranks) once, in turn, and there are --repeat rounds: a slow spell of the
machine then falls on every configuration alike instead of on one configuration's consecutive runs
(this VM's timings drift by 10 to 50 % over minutes). Prints, per configuration, the medians over the
rounds of the time per Newton iteration and of its stages (as bench_scale.py measures them), and its
speed-up against the first rank count of the same deck.
"""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_scale import run_once  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("exe")
    ap.add_argument("--decks", required=True, help="comma-separated deck files")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--work", default="bench_compare")
    ap.add_argument("--mpiexec", default="mpirun")
    a = ap.parse_args()
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    decks = a.decks.split(",")
    ranks = [int(r) for r in a.ranks.split(",")]
    configs = [(d, r) for d in decks for r in ranks]
    runs = {c: [] for c in configs}
    for round_ in range(a.repeat):
        for deck, r in configs:
            name = os.path.splitext(os.path.basename(deck))[0]
            out = os.path.join(a.work, f"{name}_np{r}_round{round_}")
            os.makedirs(a.work, exist_ok=True)
            result = run_once(a.exe, deck, out, r, a.mpiexec)
            if not result["complete"]:
                raise SystemExit(f"bench_compare: {deck} on {r} rank(s) did not complete (see {out})")
            runs[(deck, r)].append(result)
            print(f"round {round_ + 1}: {name} on {r} rank(s): {result['stage']['total']:.4f} s per iteration",
                  flush=True)
    print(f"\n{'deck':<28} {'ranks':>5} | {'s/iter':>8} {'search':>8} {'assembly':>8} {'solve':>8} | "
          f"{'speed-up':>8} {'iters':>5}  (medians of {a.repeat}, interleaved)")
    for deck, r in configs:
        med = {k: statistics.median(x["stage"][k] for x in runs[(deck, r)]) for k in runs[(deck, r)][0]["stage"]}
        base = statistics.median(x["stage"]["total"] for x in runs[(deck, ranks[0])])
        name = os.path.splitext(os.path.basename(deck))[0]
        print(f"{name:<28} {r:>5} | {med['total']:8.4f} {med['search']:8.4f} {med['assembly']:8.4f} "
              f"{med['solve']:8.4f} | {base / med['total']:8.2f} {runs[(deck, r)][0]['iterations']:>5}")


if __name__ == "__main__":
    main()
