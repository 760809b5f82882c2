#!/usr/bin/python3
"""Benchmark of scale (not a test): two crossed layers of n x n beams laid on each other, every crossing of
the top layer loaded (`beamcontact generate grid --n n --m n --elements n+1 --gap 0 --press 0 --load P`:
crossings on nodes, pinned ends, radius 1, E 1e5, spacing 10, span L = 10 (n + 1)), so that all n^2
crossings are in contact, run with each strategy on 1 and 2 ranks. P keeps the layers' deflection at
about a tenth of the radius at every size: P = 0.1 * 384 E I / (5 n L^3), the midspan deflection of a
beam carrying its n loads smeared over its span. Frictionless by default (--friction): with friction
0.2 the 16 x 16 layers do not converge from the touching start (slip directions cycling), which is a
robustness matter, not one of cost per iteration. With --model weave: the plain-weave mat of
`beamcontact generate weave --n n --m n` (8 elements per spacing, warp ends pulled). Per size, strategy
and rank count it prints
  - the time per Newton iteration (all of the run's Newton iterations, also those of cut increments),
    split into contact search (the candidate search and the points' update before each iteration),
    assembly (residual and tangent: beams and contact), linear solve, and the rest of the iteration
    (step bound and active-set passes);
  - Newton iterations, whether the run completed, active contact points at its end;
  - the peak resident memory of the largest process (the growth from the smallest to the largest size
    over the crossings added is printed as the memory per crossing);
and, per strategy and rank count, the growth exponent of each stage over the sizes (least-squares
slope of log time per iteration against log crossings), and the 2-rank speed-up (time per iteration on
1 rank over that on 2). Each figure is the median of --repeat runs (VTK off). The timings come from the
run's timers.txt (Teuchos stacked timers of rank 0).
Usage: bench_scale.py BEAMCONTACT [--sizes 4,8,16,32] [--strategies ...] [--ranks 1,2] [--repeat 3]
                      [--model grid] [--increments 5] [--friction MU] [--solver Direct|UMFPACK|MueLu|ILUT|RILUK] [--reuse] [--work DIR]
                      [--mpiexec mpirun]
"""
import argparse
import csv
import math
import os
import re
import statistics
import subprocess
import sys

STAGES = {"search": ["Contact Search", "Graph Rebuild"], "assembly": ["Assembly"], "solve": ["Linear Solve"],
          "rest": ["Step Bound", "Active Set"]}
SHORT = {"Penalty": "P", "Lagrange Multiplier": "LM", "Augmented Lagrange": "AL"}


def timers(path):
    """{timer name: (seconds, calls)} of the first level under BeamContact in timers.txt."""
    out = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"\|   ([A-Za-z ]+): ([0-9.eE+-]+) - [0-9.eE+-]+% \[(\d+)\]", line)
            if m:
                out[m.group(1)] = (float(m.group(2)), int(m.group(3)))
    return out


def run_once(exe, deck, out, ranks, mpiexec):
    cmd = [exe, "run", deck, "--output", out]  # not --quiet: the header line gives the node count
    if ranks > 1:
        cmd = [mpiexec, "-np", str(ranks), "--oversubscribe"] + cmd
    # The child's own resource use (wait4): its peak resident memory, or with mpirun that of its
    # largest rank [kB].
    with open(os.path.join(os.path.dirname(out), "bench_output.txt"), "w") as log:
        child = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(child.pid, 0)
    returncode = os.waitstatus_to_exitcode(status)
    with open(os.path.join(os.path.dirname(out), "bench_output.txt")) as log:
        nodes = re.search(r"(\d+) nodes", log.read())
    peak = usage.ru_maxrss
    if not os.path.exists(os.path.join(out, "timers.txt")):
        raise SystemExit(f"bench_scale: {' '.join(cmd)} exited with {returncode} and wrote no timers; "
                         f"its output is in {os.path.join(os.path.dirname(out), 'bench_output.txt')}")
    t = timers(os.path.join(out, "timers.txt"))
    iterations = t.get("Linear Solve", (0.0, 0))[1]
    with open(os.path.join(out, "steps.csv")) as f:
        converged = sum(int(row["newton_iterations"]) for row in csv.DictReader(f))
    with open(os.path.join(out, "contact_points.csv")) as f:
        rows = list(csv.DictReader(f))
    last = rows[-1]["step"] if rows else None
    active = sum(1 for row in rows if row["step"] == last and row["active"] == "1")
    stage = {k: sum(t.get(n, (0.0, 0))[0] for n in names) / max(iterations, 1) for k, names in STAGES.items()}
    stage["total"] = sum(stage.values())
    return {"stage": stage, "iterations": iterations, "converged_iterations": converged, "complete": returncode == 0,
            "active": active, "peak_kb": peak,
            "dofs": 6 * int(nodes.group(1)) if nodes else 0}


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(max(y, 1e-12)) for y in ys]
    mx, my = statistics.mean(lx), statistics.mean(ly)
    den = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / den if den > 0 else float("nan")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("--sizes", default="4,8,16,32")
    ap.add_argument("--strategies", default="Penalty,Lagrange Multiplier,Augmented Lagrange")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--increments", type=int, default=5)
    ap.add_argument("--model", default="grid", choices=["grid", "weave"],
                    help="grid: the loaded crossed layers above; weave: generate weave --n n --m n (plain-weave "
                         "mat, 8 elements per spacing, warp pulled)")
    ap.add_argument("--friction", type=float, default=None,
                    help="Coulomb coefficient; default 0 for the grid, 0.2 for the weave (frictionless yarns slide "
                         "freely along each other)")
    ap.add_argument("--solver", default="Direct", choices=["Direct", "UMFPACK", "MUMPS", "MueLu", "ILUT", "RILUK"],
                    help="Direct (KLU2), Direct with UMFPACK or with MUMPS, or GMRES preconditioned by MueLu multigrid, ILUT or "
                         "RILUK")
    ap.add_argument("--reuse", action="store_true",
                    help="Direct, UMFPACK or MUMPS with Reuse Factorization: GMRES preconditioned with the last factorization, "
                         "factoring again once the iterations since the last factorization reach Reuse Iteration "
                         "Limit (Automatic)")
    ap.add_argument("--work", default="bench_scale")
    ap.add_argument("--mpiexec", default="mpirun")
    a = ap.parse_args()
    if a.friction is None:
        a.friction = 0.0 if a.model == "grid" else 0.2
    os.makedirs(a.work, exist_ok=True)
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    sizes = [int(s) for s in a.sizes.split(",")]
    strategies = a.strategies.split(",")
    rank_counts = [int(r) for r in a.ranks.split(",")]
    results, memory = {}, {}
    print(f"{'n x n':>7} {'cross':>6} {'dofs':>7} {'method':>4} {'ranks':>5} | {'s/iter':>8} {'search':>8} {'assembly':>8} "
          f"{'solve':>8} {'rest':>8} | {'iters':>5} {'done':>4} {'active':>6} {'MB':>7}")
    for n in sizes:
        base = os.path.join(a.work, f"{a.model}{n}.xml")
        if a.model == "grid":
            span = 10.0 * (n + 1)
            load = 0.1 * 384 * 1e5 * math.pi / 4 / (5 * n * span ** 3)
            options = ["--elements", str(n + 1), "--gap", "0", "--press", "0", "--load", repr(load)]
        else:
            options = []
        subprocess.run([a.exe, "generate", a.model, "--n", str(n), "--m", str(n), "--friction", str(a.friction),
                        "--increments", str(a.increments), "--overwrite", "--output", base] + options, check=True, capture_output=True)
        text = open(base).read()
        for strategy in strategies:
            deck = os.path.join(a.work, f"{a.model}{n}_{SHORT.get(strategy, strategy)}.xml")
            t = text.replace('name="Type" type="string" value="Penalty"', f'name="Type" type="string" value="{strategy}"', 1)
            linear = ""
            if a.solver in ("Direct", "UMFPACK", "MUMPS"):
                direct = "KLU2" if a.solver == "Direct" else a.solver
                linear = (f'<ParameterList name="Linear Solver"><Parameter name="Direct Solver" type="string" '
                          f'value="{direct}"/><Parameter name="Reuse Factorization" type="bool" '
                          f'value="{"true" if a.reuse else "false"}"/></ParameterList>')
            else:
                if a.solver == "MueLu" and strategy == "Lagrange Multiplier":
                    continue  # multigrid takes matrices without multiplier rows
                linear = ('<ParameterList name="Linear Solver"><Parameter name="Type" type="string" value="GMRES"/>'
                          f'<Parameter name="Preconditioner" type="string" value="{a.solver}"/></ParameterList>')
            t = t.replace('<ParameterList name="BeamContact">', '<ParameterList name="BeamContact"><ParameterList '
                          'name="Output"><Parameter name="Write VTK" type="bool" value="false"/></ParameterList>' + linear, 1)
            with open(deck, "w") as f:
                f.write(t)
            for ranks in rank_counts:
                runs = [run_once(a.exe, deck, deck[:-4] + f"_np{ranks}", ranks, a.mpiexec) for _ in range(a.repeat)]
                med = {k: statistics.median(r["stage"][k] for r in runs) for k in runs[0]["stage"]}
                peak = statistics.median(r["peak_kb"] for r in runs)
                r0 = runs[0]
                results[(n, strategy, ranks)] = med
                memory[(n, strategy, ranks)] = peak
                print(f"{n:>3} x {n:<3} {n * n:>6} {r0['dofs']:>7} {SHORT.get(strategy, strategy):>4} {ranks:>5} | "
                      f"{med['total']:8.4f} {med['search']:8.4f} {med['assembly']:8.4f} {med['solve']:8.4f} "
                      f"{med['rest']:8.4f} | {r0['iterations']:>5} {'yes' if r0['complete'] else 'no':>4} "
                      f"{r0['active']:>6} {peak / 1024:7.1f}", flush=True)
    if len(sizes) > 1:
        print("\ngrowth exponent of the time per Newton iteration against crossings (log-log slope), and the "
              "2-rank speed-up (1-rank time / 2-rank time) at each size")
        for strategy in strategies:
            if any((n, strategy, r) not in results for n in sizes for r in rank_counts):
                continue
            for ranks in rank_counts:
                parts = []
                for k in ("total", "search", "assembly", "solve"):
                    parts.append(f"{k} {slope([n * n for n in sizes], [results[(n, strategy, ranks)][k] for n in sizes]):.2f}")
                print(f"  {strategy:20s} {ranks} rank(s): " + ", ".join(parts))
                if len(sizes) > 1:
                    lo, hi = sizes[0], sizes[-1]
                    per = (memory[(hi, strategy, ranks)] - memory[(lo, strategy, ranks)]) / (hi * hi - lo * lo)
                    print(f"  {strategy:20s} {ranks} rank(s): memory per crossing (peak growth {lo}x{lo} -> {hi}x{hi} "
                          f"over the crossings added) {per:.1f} kB")
            if 1 in rank_counts and 2 in rank_counts:
                speed = [results[(n, strategy, 1)]["total"] / results[(n, strategy, 2)]["total"] for n in sizes]
                print(f"  {strategy:20s} speed-up on 2 ranks: " + ", ".join(f"{n}x{n} {s:.2f}" for n, s in zip(sizes, speed)))


if __name__ == "__main__":
    main()
