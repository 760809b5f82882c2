#!/usr/bin/python3
"""Crossing-angle sweep of two clamped circular beams pressed together, frictionless (all-angle
contact). Beam A: along X, length 100, 20 elements; beam B: length 60, 12 elements, turned by alpha
about the common centre (50, 0) in the XY plane, its axis 1.1 above A's (gap 0.1, r = 0.5 each), its
clamped ends moved down by 0.12 (closure 0.02). Every inner node holds uy: two rods lying parallel
and pressed together are laterally unstable (a rod on a rod rolls off), which is not the point here.

Checks, for Penalty (eps_N 1e4, Regularization Gap 1e-3), Augmented Lagrange (Gap Tolerance 1e-6,
Maximum Iterations 50) and Lagrange multipliers (a mortar field on line A's nodes in line contact):
  - every angle completes (90 .. 0 degrees);
  - at 90 and 30 degrees (point contact at the centres) the small-displacement closed form: the
    centre compliances of the clamped beams c = L^3 / (192 E I) in series (1 %); Penalty adds the
    penetration of its smoothed law, N c + sqrt(2 g0 N / eps_N) = closure; augmented Lagrange
    N c = closure;
  - continuity through the blend of point and line contact and down to line contact: from 16 down to
    0.5 degrees each angle's normal force within 1 % of the previous one.
Lagrange multipliers (and augmented Lagrange, on the same field) enforce line contact on gaps weighted
over beam A's elements (length 5 here). At 5 to 1 degrees the contact zone around the crossing is
shorter than that: on the unrefined field the beams penetrated between its nodes and the force fell
short (by 78 % at 5 degrees). The field is now refined where a zone ends inside an element, with Gauss
points of its own in each part (docs/contact.md, "Contact zones shorter than an element"), so every
angle must end with its line points within 1e-4 of the radius of each other (no warning in status.txt,
which must come exactly when a line point penetrates by more than 1e-3 of the radius). The refined
field must converge with the beams' mesh: at 5 degrees, Lagrange on 20/12, 40/24 and 80/48 elements
(the field refines to parts of the same length on each), the differences of successive forces fall by
at least 3 (second order: 4; measured 3.96). At 0 degrees B touches A at its clamped ends only: the
force of two point loads there (closed form below, 0.5 %).
Below 2 degrees B's clamped ends come over A and the force rises steeply (geometry, not a jump).
At 0.3 degrees Lagrange on 20/12 elements within 2 % of 80/48's force (a zone ending beside its
deepest points).
Usage: angle_sweep.py BEAMCONTACT WORKDIR
"""
import csv
import math
import os
import subprocess
import sys

ANGLES = [90, 30, 16, 15, 14, 12, 10, 8, 6, 5, 4, 2, 1, 0.5, 0]
E, R, GAP, W, EPS, G0 = 1e5, 0.5, 0.1, 0.12, 1e4, 1e-3


def deck(alpha, strategy, n=20, nb=12):
    a = math.radians(alpha)
    b0 = (50 - 30 * math.cos(a), -30 * math.sin(a), 2 * R + GAP)
    b1 = (50 + 30 * math.cos(a), 30 * math.sin(a), 2 * R + GAP)

    def beam(name, s, e, k):
        return (f'<ParameterList name="{name}"><Parameter name="Start" type="Array(double)" value="{{{s[0]}, {s[1]}, {s[2]}}}"/>'
                f'<Parameter name="End" type="Array(double)" value="{{{e[0]}, {e[1]}, {e[2]}}}"/>'
                f'<Parameter name="Elements" type="int" value="{k}"/><ParameterList name="Section">'
                f'<Parameter name="Shape" type="string" value="Circle"/><Parameter name="Radius" type="double" value="{R}"/>'
                f'</ParameterList><ParameterList name="Material"><Parameter name="Young\'s Modulus" type="double" value="{E}"/>'
                f'<Parameter name="Poisson\'s Ratio" type="double" value="0.3"/></ParameterList></ParameterList>')

    def support(name, b, node, fixed, uz=0.0):
        return (f'<ParameterList name="{name}"><Parameter name="Beam" type="string" value="{b}"/>'
                f'<Parameter name="Node" type="string" value="{node}"/><Parameter name="Fixed" type="string" value="{fixed}"/>'
                f'<Parameter name="Displacement" type="Array(double)" value="{{0, 0, {uz}}}"/></ParameterList>')

    supports = support("A start", "A", "start", "all") + support("A end", "A", "end", "all")
    supports += support("B start", "B", "start", "all", -W) + support("B end", "B", "end", "all", -W)
    supports += "".join(support(f"{b} {i}", b, str(i), "uy") for b, k in (("A", n), ("B", nb)) for i in range(1, k))
    law = {"Penalty": f'<Parameter name="Regularization Gap" type="double" value="{G0}"/>',
           "Augmented Lagrange": "", "Lagrange Multiplier": ""}[strategy]
    params = "" if strategy == "Lagrange Multiplier" else (
        f'<ParameterList name="{strategy}"><Parameter name="Normal Penalty Parameter" type="double" value="{EPS}"/>'
        f'<Parameter name="Tangential Penalty Parameter" type="double" value="{EPS / 10}"/>{law}</ParameterList>')
    return (f'<ParameterList name="BeamContact"><ParameterList name="Beams">{beam("A", (0, 0, 0), (100, 0, 0), n)}'
            f'{beam("B", b0, b1, nb)}</ParameterList><ParameterList name="Supports">{supports}</ParameterList>'
            f'<ParameterList name="Contact"><ParameterList name="Pairs"><ParameterList name="AB">'
            f'<Parameter name="Beam A" type="string" value="A"/><Parameter name="Beam B" type="string" value="B"/>'
            f'<Parameter name="Friction Coefficient" type="double" value="0"/></ParameterList></ParameterList>'
            f'<ParameterList name="Enforcement"><Parameter name="Type" type="string" value="{strategy}"/>{params}'
            f'</ParameterList></ParameterList><ParameterList name="Load Stepping">'
            f'<Parameter name="Number of Increments" type="int" value="10"/></ParameterList>'
            f'<ParameterList name="Nonlinear Solver"><Parameter name="Maximum Iterations" type="int" value="50"/></ParameterList>'
            f'<ParameterList name="Output"><Parameter name="Write VTK" type="bool" value="false"/></ParameterList></ParameterList>')


def run(exe, work, alpha, strategy, n=20, nb=12):
    name = f"{strategy.replace(' ', '_')}_{alpha}" + ("" if n == 20 else f"_{n}")
    path = os.path.join(work, name + ".xml")
    with open(path, "w") as f:
        f.write(deck(alpha, strategy, n, nb))
    out = os.path.join(work, name)
    r = subprocess.run([exe, "run", path, "--output", out, "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        return None, r.stderr.strip()
    with open(os.path.join(out, "contact_points.csv")) as f:
        rows = list(csv.DictReader(f))
    last = [x for x in rows if x["step"] == rows[-1]["step"] and x["active"] == "1"]
    lines = sum(1 for x in last if int(x["line_A"]) < 0)
    with open(os.path.join(out, "status.txt")) as f:
        warned = any(line.startswith("warning:") and "not resolved" in line for line in f)
    deepest = max([-float(x["gap"]) for x in last if int(x["line_A"]) < 0] + [0.0])
    return (sum(float(x["normal_force"]) for x in last), len(last) - lines, lines, warned, deepest), ""


def penalty_force(c, closure):
    """The force N of Penalty's smoothed law (eps_N EPS, Regularization Gap G0) through a compliance c
    closing `closure`: N c + sqrt(2 G0 N / EPS) = closure, by bisection."""
    lo, hi = 0.0, closure / c
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if mid * c + math.sqrt(2 * G0 * mid / EPS) < closure else (lo, mid)
    return 0.5 * (lo + hi)


def main():
    exe, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    EI = E * math.pi * R ** 4 / 4
    c = (100.0 ** 3 + 60.0 ** 3) / (192 * EI)
    closure = W - GAP
    exact = {"Penalty": penalty_force(c, closure), "Augmented Lagrange": closure / c, "Lagrange Multiplier": closure / c}
    failures = 0
    print("angle   " + "".join(f"{s:>34s}" for s in exact))
    table = {s: {} for s in exact}
    parallel = {}
    for alpha in ANGLES:
        line = f"{alpha:5}   "
        for strategy in exact:
            result, error = run(exe, work, alpha, strategy)
            if result is None:
                line += f"{'FAILED':>34s}"
                print(f"{strategy} at {alpha} degrees: {error[-300:]}")
                failures += 1
                continue
            # The warning comes exactly when a line point penetrates by more than 1e-3 of the radius;
            # the multiplier field, refined where it must, leaves none deeper than 1e-4 of it (at
            # every angle but 0, where B's clamped ends press on A).
            if result[3] != (result[4] > 1e-3 * R):
                print(f"{strategy} at {alpha} degrees: penetration {result[4]:.2e} of line points, warning "
                      f"{'given' if result[3] else 'missing'}")
                failures += 1
            if strategy != "Penalty" and alpha > 0 and not result[4] <= 1e-4 * R:
                print(f"{strategy} at {alpha} degrees: line points penetrate by {result[4]:.2e}, more than "
                      f"1e-4 of the radius")
                failures += 1
            if not result[3]:
                table[strategy][alpha] = result[0]
            if alpha == 0:
                parallel[strategy] = result[0]
            line += f"{result[0]:16.9f} ({result[1]} points, {result[2]:2d} line){'*' if result[3] else ' '}"
        print(line)
    for strategy, values in table.items():
        for alpha in (90, 30):
            if alpha in values:
                err = abs(values[alpha] - exact[strategy]) / exact[strategy]
                print(f"{strategy} at {alpha} degrees: N = {values[alpha]:.9f}, closed form {exact[strategy]:.9f}, "
                      f"relative difference {err:.2e}")
                failures += not (err < 0.01)
        blend = [a for a in ANGLES if 0.5 <= a <= 16]
        worst = max((abs(values[b] - values[a]) / values[a], a, b) for a, b in zip(blend, blend[1:])
                    if a in values and b in values)
        print(f"{strategy}: largest change between neighbouring angles from 16 to 0.5 degrees "
              f"{worst[0]:.2e} ({worst[1]} -> {worst[2]})")
        failures += not (worst[0] < 0.01)
    # At 0 degrees B lies along A from x = 20 to 80 and touches it only at its clamped ends, which its
    # supports hold 0.02 into A: two point forces P on the clamped-clamped A at a = 20 and L - a, each
    # closing 0.02 with A's deflection there (B, clamped at the point, adds none). A's deflection under
    # a load P at a (b = L - a): P a^3 b^3 / (3 L^3 EI); under the load at L - a, at x = a:
    # P a^2 a^2 (3 b L - 3 b a - a a) / (6 L^3 EI). The multiplier field refines towards B's ends (the
    # contact zone ends inside A's elements there) and must carry 2 P within 0.5 %.
    L, a = 100.0, 20.0
    b = L - a
    per_load = (a ** 3 * b ** 3 / 3 + a ** 4 * (3 * b * L - 3 * b * a - a * a) / 6) / (L ** 3 * EI)
    ends = 2 * closure / per_load
    for strategy in ("Lagrange Multiplier", "Augmented Lagrange"):
        if strategy in parallel:
            err = (parallel[strategy] - ends) / ends
            print(f"{strategy} at 0 degrees: N = {parallel[strategy]:.9f}, two point loads at B's ends {ends:.9f}, "
                  f"relative difference {err:.2e}")
            failures += not (abs(err) < 5e-3)
    # Mesh convergence of the refined field at 5 degrees (Lagrange multipliers).
    forces = []
    for n, nb in ((20, 12), (40, 24), (80, 48)):
        result, error = run(exe, work, 5, "Lagrange Multiplier", n, nb)
        if result is None:
            print(f"Lagrange Multiplier at 5 degrees, {n}/{nb} elements: {error[-300:]}")
            failures += 1
            continue
        forces.append(result[0])
        print(f"Lagrange Multiplier at 5 degrees, {n}/{nb} elements: N = {result[0]:.9f}, deepest line point "
              f"{result[4]:.2e}")
    if len(forces) == 3:
        rate = abs(forces[0] - forces[1]) / max(abs(forces[1] - forces[2]), 1e-300)
        print(f"differences of successive forces {forces[1] - forces[0]:.3e}, {forces[2] - forces[1]:.3e}: "
              f"ratio {rate:.2f}")
        failures += not (rate > 3.0)
    # At 0.3 degrees the zone (about 7 long, around x = 28 and 72) ends inside elements whose own Gauss
    # points neither penetrate nor open by 1e-4 of the radius while their neighbours' do: Lagrange on
    # 20/12 elements ended 2.7 % below 80/48's force without a warning. Now within 2 % of it (measured
    # -1.5 %; 10/6 and 40/24 +1.0 % and +0.4 % of it).
    fine, error = run(exe, work, 0.3, "Lagrange Multiplier", 80, 48)
    coarse, error2 = run(exe, work, 0.3, "Lagrange Multiplier", 20, 12)
    if fine is None or coarse is None:
        print(f"Lagrange Multiplier at 0.3 degrees: {(error or error2)[-300:]}")
        failures += 1
    else:
        err = (coarse[0] - fine[0]) / fine[0]
        print(f"Lagrange Multiplier at 0.3 degrees: N = {coarse[0]:.9f} (20/12 elements), {fine[0]:.9f} (80/48): "
              f"relative difference {err:+.2e}")
        failures += not (abs(err) < 0.02)
    if failures:
        sys.exit(f"{failures} check(s) failed")
    print("ok")


if __name__ == "__main__":
    main()
