#!/usr/bin/python3
"""B's clamped ends pressed onto a parallel beam A inside A's elements (line contact, multiplier field).

The deck of angle_sweep.py at 0 degrees (two circular beams, A clamped at x = 0 and 100 with 20
elements, B of length 60 with 12 elements lying along A, its clamped ends moved down by 0.12 against
a gap of 0.1, frictionless), with B moved along A by SHIFT, so that B's ends lie SHIFT past A's nodes
at x = 20 and 80: inside A's elements (length 5) by 0.4 %, 2 %, 5 %, 20 % and 50 %, and on A's nodes
at 25 and 85 (which A's axial motion moves B's ends off by round-off: that cut came and went between
Newton's iterations, and both strategies stopped at first contact). B touches A at its two ends
only: two point forces P1, P2 on the clamped-clamped A at a1 = 20 + SHIFT and a2 = 80 + SHIFT, each
closing 0.02 with A's deflection there (B, clamped at the point, adds none):
    w(a_i) = sum_j P_j G(a_i, a_j) = 0.02,
G the clamped-clamped beam's influence function (for x <= a: P b^2 x^2 (3 a L - 3 a x - b x) / (6 L^3 EI),
b = L - a; by symmetry beyond). The total P1 + P2 is the reference.

Lagrange multipliers and Augmented Lagrange carry the contact on a field on A's nodes. A free end of B
inside an element of A cuts that element's field: the node beyond the end carries a point at the end
(its row the gap there), the piece's Gauss points the element's other node (docs/contact.md, "A free
end of B inside an element"). Before, the part's hats were stretched over the piece (Lagrange 8.4 % and
10 % low at 20 % and 50 %, with a penetration warning; Augmented Lagrange 2.8 % low at 20 %, and 1.2 %
low without a warning at 8 %), and before that Augmented Lagrange ran out of passes at 2 %.

Checks, each shift: both strategies complete without the unresolved-zone warning; the total force is
within 0.5 % of P1 + P2 (measured +0.115 % to +0.157 % at every shift: the closed form is linear);
Augmented Lagrange equals Lagrange within 1e-4 of it.

Then 2 x 1 rectangles (width along y, B's bottom face on A's top face, equal widths), B's ends on A's
nodes and 0.1 past them, each strategy, the same checks; Penalty against the two point forces that
close the closure less its deepest penetration (its smoothed law's, at B's ends). Before, Lagrange
stopped at T = 0.96 on a singular matrix (B's end point, a rectangle's end face within line contact's
angles of A's face, beside the field's rows for the same place) and Augmented Lagrange at first contact
(a node beyond B's end covering a sliver of 6e-6 of an element, A's axial motion, with a row of that
weight).
Then the short beam B as the pair's A (the field on its own edges, whose end nodes keep their multipliers:
no held node of the long beam beside them along the normal), circles at 0.1 and 1 (Lagrange, Augmented
Lagrange), rectangles at 0.1 (each strategy), and at 2.5 on 40/24 elements, where its ends lie on the long
beam's nodes that hold uy only (Lagrange): the same checks. Before, with its end nodes merged, 36 % low.
Usage: parallel_ends.py BEAMCONTACT WORKDIR
"""
import csv
import os
import re
import subprocess
import sys

import angle_sweep

SHIFTS = [0.02, 0.1, 0.25, 1.0, 2.5, 5.0]
# Rectangles 2 wide and 1 high (B's bottom face on A's top face, equal widths: A's edges carry the
# contact), B's ends on A's nodes (shift 0) and 0.1 past them; each strategy.
RECTANGLE_SHIFTS = [0.0, 0.1]
RECTANGLE_STRATEGIES = ("Penalty", "Lagrange Multiplier", "Augmented Lagrange")
# The short beam B as the pair's A: the field lies on its edges, whose end elements end at its clamped
# ends (pressing the long beam's free interior).
SWAPPED_SHIFTS = [0.1, 1.0]
WIDTH, HEIGHT = 2.0, 1.0
L, CLOSURE = 100.0, 0.02
CIRCLE = ('<Parameter name="Shape" type="string" value="Circle"/>'
          f'<Parameter name="Radius" type="double" value="{angle_sweep.R}"/>')
RECTANGLE = ('<Parameter name="Shape" type="string" value="Rectangle"/>'
             f'<Parameter name="Width" type="double" value="{WIDTH}"/><Parameter name="Height" type="double" value="{HEIGHT}"/>')


PAIR = '<Parameter name="Beam A" type="string" value="A"/><Parameter name="Beam B" type="string" value="B"/>'


def deck(strategy, shift, rectangle=False, swapped=False, n=20, nb=12, increments=10):
    xml = angle_sweep.deck(0, strategy, n, nb)
    steps = '<Parameter name="Number of Increments" type="int" value="10"/>'
    assert xml.count(steps) == 1
    xml = xml.replace(steps, steps.replace('"10"', f'"{increments}"'))
    if swapped:
        assert xml.count(PAIR) == 1
        xml = xml.replace(PAIR, PAIR.replace('"A"', '"@"').replace('"B"', '"A"').replace('"@"', '"B"'))
    if rectangle:
        assert xml.count(CIRCLE) == 2
        xml = xml.replace(CIRCLE, RECTANGLE)
    start = xml.index('<ParameterList name="B">')

    def moved(m):
        v = [float(x) for x in m.group(2).split(",")]
        v[0] += shift
        return f'{m.group(1)}{{{v[0]!r}, {v[1]!r}, {v[2]!r}}}"'

    beam_b = re.sub(r'(name="(?:Start|End)" type="Array\(double\)" value=")\{([^}]*)\}"', moved, xml[start:], count=2)
    return xml[:start] + beam_b


def influence(x, a, EI):
    if x > a:
        return influence(L - x, L - a, EI)
    b = L - a
    return b * b * x * x * (3 * a * L - 3 * a * x - b * x) / (6 * L ** 3 * EI)


def reference(shift, rectangle=False):
    import math
    # (bending in z: a rectangle's width along y, its height along z)
    EI = angle_sweep.E * (WIDTH * HEIGHT ** 3 / 12 if rectangle else math.pi * angle_sweep.R ** 4 / 4)
    a1, a2 = 20 + shift, 80 + shift
    g11, g12, g21, g22 = influence(a1, a1, EI), influence(a1, a2, EI), influence(a2, a1, EI), influence(a2, a2, EI)
    det = g11 * g22 - g12 * g21
    p1 = CLOSURE * (g22 - g12) / det
    p2 = CLOSURE * (g11 - g21) / det
    return p1 + p2


def run(exe, work, strategy, shift, rectangle=False, swapped=False, n=20, nb=12, increments=10):
    name = (f"{strategy.replace(' ', '_')}_{shift}" + ("_rectangle" if rectangle else "") +
            ("_swapped" if swapped else "") + ("" if n == 20 else f"_{n}") +
            ("" if increments == 10 else f"_{increments}increments"))
    path = os.path.join(work, name + ".xml")
    with open(path, "w") as f:
        f.write(deck(strategy, shift, rectangle, swapped, n, nb, increments))
    out = os.path.join(work, name)
    r = subprocess.run([exe, "run", path, "--output", out, "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        return None, r.stderr.strip()[-300:]
    with open(os.path.join(out, "contact_points.csv")) as f:
        rows = list(csv.DictReader(f))
    last = [x for x in rows if x["step"] == rows[-1]["step"] and x["active"] == "1"]
    with open(os.path.join(out, "status.txt")) as f:
        warned = any(line.startswith("warning:") and "not resolved" in line for line in f)
    deepest = max([-float(x["gap"]) for x in last] + [0.0])
    return (sum(float(x["normal_force"]) for x in last), warned, deepest), ""


def check_shift(exe, work, shift, strategies, rectangle, swapped=False, n=20, nb=12):
    """Runs one shift with each strategy; returns the number of failed checks."""
    exact = reference(shift, rectangle)
    label = (f"{'rectangles, ' if rectangle else ''}B's ends {shift} past A's nodes"
             f"{' (the short beam as the pair' + chr(39) + 's A)' if swapped else ''}"
             f"{'' if n == 20 else f', {n}/{nb} elements'}")
    failures = 0
    forces = {}
    for strategy in strategies:
        result, error = run(exe, work, strategy, shift, rectangle, swapped, n, nb)
        if result is None:
            print(f"{strategy}, {label}: {error}")
            failures += 1
            continue
        force, warned, deepest = result
        forces[strategy] = force
        # (Penalty's smoothed law takes part of the closure as its penetration at B's ends: the two
        # point forces then close what is left, the forces being linear in the closure.)
        penalty = strategy == "Penalty"
        expected = exact * (1 - deepest / CLOSURE) if penalty else exact
        err = (force - expected) / expected
        print(f"{strategy}, {label}: N = {force:.9f}, two point forces {expected:.9f}"
              f"{f' (closure less the deepest penetration {deepest:.3e})' if penalty else ''}, "
              f"relative difference {err:+.2e}{', unresolved-zone warning' if warned else ''}")
        failures += warned or not abs(err) < 0.005
    if "Lagrange Multiplier" in forces and "Augmented Lagrange" in forces:
        d = abs(forces["Augmented Lagrange"] - forces["Lagrange Multiplier"]) / exact
        print(f"  Augmented Lagrange against Lagrange: {d:.2e}")
        failures += not d < 1e-4
    return failures


def check_increments(exe, work):
    """Penalty, rectangles 0.02 past A's nodes, the short beam as A, 10/6 elements: B's end elements and
    A's turn from below 0.03 degrees to above 0.057 in the increment of first contact (T = 0.83), into
    the rectangles' blend of line and point contact (0.057 to 0.115 degrees), where B's ends carry end
    points weighted by the blend at their element's angle. The problem is frictionless and elastic: its
    answer does not depend on the path. Before, a pair's kinds of points were chosen by its angle at
    the last converged state only: with 5 increments (that state at T = 0.8, before contact) B's ends
    had no end point and the force was 2.7 % below 10 increments' (0.34090 against 0.35019), "complete",
    with no warning; and the end point at x = 20.02 stayed on whichever of A's elements beside the node
    at x = 20 it was found on (5 % of an element's hysteresis), whose angles differ: 0.34558 with 1 and 5
    increments, 0.35019 with 10. Checks, with 1, 5 and 10 increments: B's two end points act at T = 1,
    the forces agree to 1e-6, and they are within 1 % of the two point forces that close the closure
    less the deepest penetration (measured -0.43 %)."""
    exact = reference(0.02, True)
    failures = 0
    forces = []
    for increments in (1, 5, 10):
        result, error = run(exe, work, "Penalty", 0.02, True, True, 10, 6, increments)
        label = f"Penalty, rectangles 0.02 past A's nodes, the short beam as A, 10/6 elements, {increments} increments"
        if result is None:
            print(f"{label}: {error}")
            failures += 1
            continue
        force, warned, deepest = result
        forces.append(force)
        name = "Penalty_0.02_rectangle_swapped_10" + ("" if increments == 10 else f"_{increments}increments")
        with open(os.path.join(work, name, "contact_points.csv")) as f:
            rows = list(csv.DictReader(f))
        ends = [x for x in rows if x["step"] == rows[-1]["step"] and x["active"] == "1" and int(x["line_A"]) >= 1000]
        expected = exact * (1 - deepest / CLOSURE)
        err = (force - expected) / expected
        print(f"{label}: N = {force:.9f}, two point forces {expected:.9f}, relative difference {err:+.2e}, "
              f"{len(ends)} end points acting")
        failures += len(ends) != 2 or not abs(err) < 0.01
    if forces:
        spread = (max(forces) - min(forces)) / max(forces)
        print(f"  spread over the increments: {spread:.2e}")
        failures += not spread < 1e-6
    return failures


def main():
    exe, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = sum(check_shift(exe, work, shift, ("Lagrange Multiplier", "Augmented Lagrange"), False)
                   for shift in SHIFTS)
    failures += sum(check_shift(exe, work, shift, RECTANGLE_STRATEGIES, True) for shift in RECTANGLE_SHIFTS)
    failures += sum(check_shift(exe, work, shift, ("Lagrange Multiplier", "Augmented Lagrange"), False, True)
                    for shift in SWAPPED_SHIFTS)
    failures += check_shift(exe, work, 0.1, RECTANGLE_STRATEGIES, True, True)
    # The short beam's ends at 22.5 and 82.5 on nodes of the long beam's 40 elements, which hold uy only
    # (not along the normal between the axes): its end nodes keep their multipliers. (Merged there, as
    # by a rule that asked only whether both were held: 22 % low, warned; rectangles stopped.)
    failures += check_shift(exe, work, 2.5, ("Lagrange Multiplier",), False, True, 40, 24)
    failures += check_shift(exe, work, 2.5, ("Lagrange Multiplier",), True, True, 40, 24)
    failures += check_increments(exe, work)
    if failures:
        sys.exit(f"{failures} check(s) failed")
    print("ok")


if __name__ == "__main__":
    main()
