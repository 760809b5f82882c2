#!/usr/bin/python3
"""Benchmark of memory (not a test): the peak resident memory of `beamcontact run` (1 rank, the decks'
Direct solver, Automatic by default: KLU2 for the elements series and small layers, UMFPACK with
Reuse Factorization for layers from 3000 unknowns; the size guard's numbers were measured with KLU2) for models of growing size, and the least-squares fit of bytes per
element and per contact point that input/Deck.cpp's size guard uses.
  - elements: Example 1 (input/example1.xml, Lagrange multipliers) with beam 1 cut into E elements (a
    handful of contact points);
  - points: the crossed layers of `beamcontact generate grid --n N --m N --gap 0 --press 0 --load P`
    (bench_scale.py's model: touching, loaded at each of the N^2 crossings, every contact point active
    from the first iteration; 2 N (N + 1) elements), with Penalty and Lagrange multipliers.
The contact points are those `beamcontact check` counts at the start. Each run is cut short after its first increment's first Newton iterations (Maximum Iterations 3,
Maximum Step Cuts 0): the model, the matrix and its factorization with every contact point are then
allocated. Later increments can need more (a longer Penalty run of the generated 32 x 32 layers,
gap 0.1, 2 increments cut 5 times: 223 MB against 169 MB for its short run), so the figures are a floor. The peak is /usr/bin/time's maximum resident set size.
Fit: peak = c + a elements over the element series; then, per strategy, peak - a elements = c' + b
points over the grid series.
Usage: bench_memory.py BEAMCONTACT [--elements 25000,50000,100000] [--grids 32,64,100,141] [--work DIR]
"""
import argparse
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def short_run(deck_text):
    """Stops after the first increment's first Newton iterations."""
    assert "Nonlinear Solver" not in deck_text and "Maximum Step Cuts" not in deck_text
    return re.sub(r'(<ParameterList[^>]*name="Load Stepping"[^>]*>)',
                  '<ParameterList name="Nonlinear Solver"><Parameter name="Maximum Iterations" type="int" value="3"/>'
                  r'</ParameterList>\1<Parameter name="Maximum Step Cuts" type="int" value="0"/>', deck_text, count=1)
    return deck_text


def peak_mb(exe, deck, out):
    r = subprocess.run(["/usr/bin/time", "-f", "PEAK %M", exe, "run", deck, "--output", out, "--quiet"],
                       capture_output=True, text=True)
    m = re.search(r"PEAK (\d+)", r.stderr)
    if not m:
        sys.exit(f"{deck}: no peak in {r.stderr[-300:]}")
    c = subprocess.run([exe, "check", deck], capture_output=True, text=True)
    points = int(re.search(r"(\d+) contact points at the start", c.stdout).group(1))
    return int(m.group(1)) / 1024.0, points


def fit(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    return slope, my - slope * mx


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("--elements", default="25000,50000,100000")
    ap.add_argument("--grids", default="32,64,100,141")
    ap.add_argument("--strategies", default="Penalty,Lagrange Multiplier")
    ap.add_argument("--work", default="bench_memory")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    with open(os.path.join(HERE, "..", "input", "example1.xml")) as f:
        example1 = f.read()
    print("series      size        elements  points  peak MB")
    xs, ys = [], []
    for e in map(int, a.elements.split(",")):
        text = short_run(example1.replace('name="Elements" type="int" value="10"',
                                          f'name="Elements" type="int" value="{e}"', 1))
        deck = os.path.join(a.work, f"beam_{e}.xml")
        with open(deck, "w") as f:
            f.write(text)
        mb, points = peak_mb(a.exe, deck, os.path.join(a.work, f"beam_{e}"))
        print(f"elements    {e:<10d}  {e + 10:8d}  {points:6d}  {mb:8.1f}", flush=True)
        xs.append(e + 10)
        ys.append(mb * 1e6 * 1.048576)
    per_element, base = fit(xs, ys)
    print(f"fit: {per_element / 1e3:.1f} kB per element, {base / 1e6:.0f} MB at 0 elements")
    for strategy in a.strategies.split(","):
        px, py = [], []
        for n in map(int, a.grids.split(",")):
            deck = os.path.join(a.work, f"grid_{n}_{strategy.split()[0]}.xml")
            # Touching layers loaded at every crossing (bench_scale.py's model): every point active from
            # the first iteration, so Lagrange multipliers' rows are there in the short run too.
            load = 0.1 * 384 * 1e5 * (3.141592653589793 / 4) / (5 * n * (10.0 * (n + 1)) ** 3)
            subprocess.run([a.exe, "generate", "grid", "--n", str(n), "--m", str(n), "--gap", "0", "--press", "0",
                            "--load", str(load), "--overwrite", "--output", deck], check=True)
            with open(deck) as f:
                text = f.read()
            text = text.replace('name="Type" type="string" value="Penalty"', f'name="Type" type="string" value="{strategy}"', 1)
            with open(deck, "w") as f:
                f.write(short_run(text))
            mb, points = peak_mb(a.exe, deck, deck[:-4])
            elements = 2 * n * (max(9, n + 1))
            print(f"{strategy.split()[0]:<10s}  {n}x{n:<7d} {elements:8d}  {points:6d}  {mb:8.1f}", flush=True)
            px.append(points)
            py.append(mb * 1e6 * 1.048576 - per_element * elements)
        per_point, rest = fit(px, py)
        print(f"fit ({strategy}): {per_point / 1e3:.1f} kB per contact point (after {per_element / 1e3:.1f} kB per element), "
              f"{rest / 1e6:.0f} MB at 0")


if __name__ == "__main__":
    main()
