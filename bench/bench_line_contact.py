#!/usr/bin/python3
"""Benchmark of line contact (not a test): the crossing of tests/cli/angle_sweep.py (two clamped
circular beams pressed together, frictionless, Penalty eps_N 1e4 with Regularization Gap 1e-3) at 8
degrees, computed
  1. with point contact only (Line Contact Angle 0) and with line contact only (Line Contact Angle 9,
     Point Contact Angle 10), 6 Gauss points per element: time per Newton iteration and per assembly
     (residual + tangent), and the normal force;
  2. with line contact only and 1 .. 30 Gauss points per element: the normal force against the one
     with 30 points (the most a deck may ask), and the time per Newton iteration.
Each figure is the median over --repeat runs (one rank, VTK off). Times per Newton iteration are the
run's solve time over its Newton iterations; assembly times come from timers.txt.
Usage: bench_line_contact.py BEAMCONTACT [--repeat N] [--work DIR]
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli"))
import angle_sweep  # noqa: E402  (the deck of the sweep)

ALPHA = 8


def deck(line_angle, point_angle, gauss):
    xml = angle_sweep.deck(ALPHA, "Penalty")
    extra = (f'<Parameter name="Line Contact Angle" type="double" value="{line_angle}"/>'
             f'<Parameter name="Point Contact Angle" type="double" value="{point_angle}"/>'
             f'<Parameter name="Line Gauss Points" type="int" value="{gauss}"/>')
    return xml.replace('<ParameterList name="Contact">', '<ParameterList name="Contact">' + extra, 1)


def run(exe, work, name, text):
    path = os.path.join(work, name + ".xml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(work, name)
    r = subprocess.run([exe, "run", path, "--output", out, "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{name} failed: {r.stderr.strip()[-300:]}")
    with open(os.path.join(out, "summary.csv")) as f:
        summary = next(csv.DictReader(f))
    with open(os.path.join(out, "contact_points.csv")) as f:
        rows = list(csv.DictReader(f))
    last = [x for x in rows if x["step"] == rows[-1]["step"] and x["active"] == "1"]
    with open(os.path.join(out, "timers.txt")) as f:
        m = re.search(r"Assembly: ([0-9.eE+-]+) .*\[(\d+)\]", f.read())
    newton = int(summary["newton_iterations"])
    return {"force": sum(float(x["normal_force"]) for x in last), "points": len(last),
            "iteration": float(summary["solve_seconds"]) / newton, "newton": newton,
            "assembly": float(m.group(1)) / int(m.group(2)) if m else float("nan")}


def median_run(exe, work, name, text, repeat):
    runs = [run(exe, work, name, text) for _ in range(repeat)]
    out = dict(runs[0])
    for key in ("iteration", "assembly"):
        out[key] = statistics.median(r[key] for r in runs)
        out[key + "_spread"] = max(r[key] for r in runs) - min(r[key] for r in runs)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--work", default="bench_line_contact")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    print(f"crossing at {ALPHA} degrees, Penalty, medians of {a.repeat} runs")
    point = median_run(a.exe, a.work, "point", deck(0, 15, 6), a.repeat)
    line = median_run(a.exe, a.work, "line", deck(9, 10, 6), a.repeat)
    print(f"{'model':8s} {'points':>7s} {'Newton':>7s} {'ms / iteration':>15s} {'ms / assembly':>14s} {'force':>12s}")
    for name, r in (("point", point), ("line", line)):
        print(f"{name:8s} {r['points']:7d} {r['newton']:7d} {1e3 * r['iteration']:9.2f} +-{1e3 * r['iteration_spread'] / 2:4.2f}"
              f" {1e3 * r['assembly']:9.3f} +-{1e3 * r['assembly_spread'] / 2:4.3f} {r['force']:12.9f}")
    print(f"line / point: {line['iteration'] / point['iteration']:.2f} per Newton iteration, "
          f"{line['assembly'] / point['assembly']:.2f} per assembly")
    print("\nline contact only, Gauss points per element of beam A vs the force with 30")
    results = {g: median_run(a.exe, a.work, f"gauss_{g}", deck(9, 10, g), a.repeat) for g in (1, 2, 4, 6, 8, 16, 30)}
    ref = results[30]["force"]
    print(f"{'Gauss':>6s} {'force':>14s} {'relative error':>15s} {'ms / iteration':>15s}")
    for g, r in results.items():
        print(f"{g:6d} {r['force']:14.9f} {abs(r['force'] - ref) / ref:15.2e} {1e3 * r['iteration']:15.2f}")


if __name__ == "__main__":
    main()
