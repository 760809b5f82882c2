#!/usr/bin/python3
"""Mesh convergence of point contact on chords and on Hermite axes: input/crossed_thick_beams.xml.

    crossed_beams_convergence.py BEAMCONTACT WORKDIR [ELEMENTS ...]

Runs the deck with each of "Chord" and "Hermite" (Contact/Point Contact Axes) at 5, 10, 20, 40 and 80
elements per beam (or the ELEMENTS given), and prints, at T = 1, the contact force's in-plane
components F_x, F_y (perpendicular to the push; beam 1's and beam 2's support reactions along X and Y
balance them), its component F_z along the push, and the contact point's position along beam 1 (x),
each with its error against the reference (Hermite axes on twice the finest mesh); then the observed
rates log2(|e_n| / |e_2n|) and whether the errors fall monotonically. The deck is edited by parameter
path, never as text.
"""
import csv
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "cli"))
from check_gold import set_parameter  # noqa: E402  (edits a deck by parameter path)
DECK = os.path.join(HERE, "..", "input", "crossed_thick_beams.xml")


def run(exe, work, axes, elements, condition_limit=None):
    tree = ET.parse(DECK)
    root = tree.getroot()
    set_parameter(root, "Contact/Point Contact Axes", "string", axes)
    if condition_limit:
        set_parameter(root, "Linear Solver/Condition Limit", "double", condition_limit)
    for beam in ("beam 1", "beam 2"):
        set_parameter(root, "Beams/" + beam + "/Elements", "int", str(elements))
    name = "%s_%d" % (axes, elements)
    deck = os.path.join(work, name + ".xml")
    tree.write(deck)
    out = os.path.join(work, name)
    r = subprocess.run([exe, "run", deck, "-o", out, "-q", "--overwrite"], capture_output=True, text=True)
    if r.returncode != 0:
        return {"failure": r.stderr.strip().splitlines()[-1] if r.stderr.strip() else "exit %d" % r.returncode}
    with open(os.path.join(out, "contact_points.csv")) as f:
        rows = [row for row in csv.DictReader(f) if row["active"] == "1"]
    last = max(int(row["step"]) for row in rows)
    rows = [row for row in rows if int(row["step"]) == last]
    fx = sum(float(row["normal_force_x"]) + float(row["tangential_force_x"]) for row in rows)
    fy = sum(float(row["normal_force_y"]) + float(row["tangential_force_y"]) for row in rows)
    fz = sum(float(row["normal_force_z"]) + float(row["tangential_force_z"]) for row in rows)
    x = float(rows[0]["x"])
    return {"Fx": fx, "Fy": fy, "Fz": fz, "x": x}


def main():
    exe, work = sys.argv[1:3]
    meshes = [int(n) for n in sys.argv[3:]] or [5, 10, 20, 40, 80]
    os.makedirs(work, exist_ok=True)
    keys = ("Fx", "Fy", "Fz", "x")
    # The reference: the Hermite axes on twice the finest mesh (elements of 0.625 at 160 per beam, 1/32 of
    # the section's diameter: the linear solver's conditioning check needs 1e16 there).
    reference = run(exe, work, "Hermite", 2 * meshes[-1], "1e16")
    if "failure" in reference:
        sys.exit("reference run: " + reference["failure"])
    print("reference (Hermite axes, %d elements): F_x %.4f, F_y %.4f, F_z %.3f, x %.5f" %
          (2 * meshes[-1], reference["Fx"], reference["Fy"], reference["Fz"], reference["x"]))
    for axes in ("Chord", "Hermite"):
        results = [run(exe, work, axes, n) for n in meshes]
        print("\n%s axes: values at T = 1 and (in brackets) their errors against the reference" % axes)
        print("| elements | F_x | F_y | F_z | x |")
        print("|---|---|---|---|---|")
        for n, r in zip(meshes, results):
            if "failure" in r:
                print("| %d | incomplete: %s |" % (n, r["failure"]))
                continue
            print("| %d | %s |" % (n, " | ".join("%.4f (%+.2e)" % (r[k], r[k] - reference[k]) for k in keys)))
        print("observed rates log2(|e_n| / |e_2n|):")
        for k in keys:
            e = [abs(r[k] - reference[k]) if "failure" not in r else float("nan") for r in results]
            rates = [math.log2(e[i] / e[i + 1]) if e[i + 1] > 0 else float("nan") for i in range(len(e) - 1)]
            monotone = all(e[i + 1] < e[i] for i in range(len(e) - 1))
            print("  %-3s %s  (%s)" % (k, "  ".join("%.2f" % v for v in rates),
                                      "monotone" if monotone else "not monotone"))


if __name__ == "__main__":
    main()
