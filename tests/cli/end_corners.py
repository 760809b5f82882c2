#!/usr/bin/python3
"""End corners: the angle sweep's deck (angle_sweep.py) with 2 x 1 rectangles (width 2 across, height 1):
beam A clamped along X (length 100), beam B (length 60) turned by alpha about the centre, its clamped
ends pressed 0.02 into A. Between about 2.3 and 3.8 degrees B's ends lie over A's top face with only
their inner lower corner (B's half width 1 across, at |y| = 30 sin(alpha) - cos(alpha) from A's axis);
no edges cross there (the edge crossings lie beyond B's ends) and B's end faces stand across A's face,
so neither point nor end contact saw them: every strategy stopped at first contact ("overlap ...
where no contact point sees them"). The corner is now a point of its own (docs/contact.md, "End
corners").

Reference: the corner belongs to B's clamped end section, which the support places exactly, so A alone
closes the 0.02 under two point loads P at x = a = 50 - 30 cos(alpha) - sin(alpha) and L - a, off A's
axis by e = 30 sin(alpha) - cos(alpha) on opposite sides: A clamped-clamped (L = 100, E = 1e5,
I = 2 / 12) deflects under its own load P a^3 b^3 / (3 L^3 EI) and under the other P a^4 (3 b L -
3 b a - a^2) / (6 L^3 EI) (b = L - a); the opposite torques e P twist the clamped A by
e P a (L - 2 a) / (L GJ) at a (G = E / 2.6, J Saint-Venant's for 2 x 1), which lowers the corner by
e times that. Lagrange multipliers and augmented Lagrange close 0.02 exactly; Penalty (eps_N 1e4,
Regularization Gap 1e-3) leaves its smoothed law's penetration sqrt(2 g0 P / eps_N). Each strategy's
total within 2e-3 of its closed form (measured +7.4e-4 to +8.7e-4; with a tenth of the closure, Lagrange
at 3 degrees -1.0e-4 from +8.0e-4: the geometric nonlinearity), carried by the two corner points alone
(their x and y within 1e-3 of the corners').
Usage: end_corners.py BEAMCONTACT WORKDIR
"""
import csv
import math
import os
import subprocess
import sys

import angle_sweep
import parallel_ends

STRATEGIES = ("Penalty", "Lagrange Multiplier", "Augmented Lagrange")
ANGLES = (2.5, 3.0, 3.5)
L, E, NU = 100.0, angle_sweep.E, 0.3


def torsion_constant(a, b):
    """Saint-Venant's torsion constant of an a x b rectangle (the series the code uses)."""
    a, b = max(a, b), min(a, b)
    s = sum(math.tanh(n * math.pi * a / (2 * b)) / n ** 5 for n in range(1, 200, 2))
    return a * b ** 3 / 3 * (1 - 192 / math.pi ** 5 * (b / a) * s)


def closed_form(alpha, strategy):
    t = math.radians(alpha)
    a = 50 - 30 * math.cos(t) - math.sin(t)
    e = 30 * math.sin(t) - math.cos(t)
    b = L - a
    EI = E * parallel_ends.WIDTH * parallel_ends.HEIGHT ** 3 / 12
    GJ = E / (2 * (1 + NU)) * torsion_constant(parallel_ends.WIDTH, parallel_ends.HEIGHT)
    # (the corner's deflection under its own load and the other, and the twist of their torques)
    c = parallel_ends.influence(a, a, EI) + parallel_ends.influence(a, b, EI) + e * e * a * (L - 2 * a) / (L * GJ)
    closure = angle_sweep.W - angle_sweep.GAP
    if strategy != "Penalty":
        return 2 * closure / c, a, e
    return 2 * angle_sweep.penalty_force(c, closure), a, e


def main():
    exe, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = 0
    for alpha in ANGLES:
        for strategy in STRATEGIES:
            name = f"{strategy.replace(' ', '_')}_{alpha}"
            path = os.path.join(work, name + ".xml")
            with open(path, "w") as f:
                f.write(angle_sweep.deck(alpha, strategy).replace(parallel_ends.CIRCLE, parallel_ends.RECTANGLE))
            out = os.path.join(work, name)
            r = subprocess.run([exe, "run", path, "--output", out, "--quiet"], capture_output=True, text=True)
            if r.returncode != 0:
                print(f"{strategy} at {alpha} degrees: {r.stderr.strip()[-300:]}")
                failures += 1
                continue
            with open(os.path.join(out, "contact_points.csv")) as f:
                rows = list(csv.DictReader(f))
            last = [x for x in rows if x["step"] == rows[-1]["step"] and x["active"] == "1"]
            total = sum(float(x["normal_force"]) for x in last)
            exact, a, e = closed_form(alpha, strategy)
            err = (total - exact) / exact
            corners = [x for x in last if int(x["line_A"]) >= 1000 and int(x["line_B"]) >= 4]
            off = max([min(abs(float(x["x"]) - a), abs(float(x["x"]) - (L - a))) + abs(abs(float(x["y"])) - e)
                       for x in corners] + [0.0])
            print(f"{alpha:4} degrees {strategy:20s}: N = {total:.6f}, closed form {exact:.6f}, relative difference "
                  f"{err:+.2e}; {len(corners)} of {len(last)} active points at corners, {off:.1e} from them")
            failures += not (abs(err) < 2e-3)
            failures += not (len(corners) == len(last) == 2 and off < 1e-3)
    if failures:
        sys.exit(f"{failures} check(s) failed")
    print("ok")


if __name__ == "__main__":
    main()
