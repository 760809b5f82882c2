#!/usr/bin/python3
"""The paper's examples on chords and on Hermite axes (Contact/Point Contact Axes), against their
discretization error.

    point_axes_examples.py BEAMCONTACT WORKDIR

Runs input/example1.xml, example2.xml and example3.xml with each strategy, on the chords and on the
Hermite axes, with the decks' 10 elements per beam and with 20; prints at T = 1 the tracked values of
the gold files (A's u_x, u_z, the total normal force; Example 1 also B's), the change Hermite - chord,
and the discretization change (20 elements - 10) of each. The decks are edited by parameter path.
"""
import csv
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "cli"))
from check_gold import set_parameter  # noqa: E402  (edits a deck by parameter path)
STRATEGIES = ("Lagrange Multiplier", "Penalty", "Augmented Lagrange")


def run(exe, work, example, strategy, axes, elements):
    tree = ET.parse(os.path.join(HERE, "..", "input", example + ".xml"))
    root = tree.getroot()
    set_parameter(root, "Contact/Enforcement/Type", "string", strategy)
    set_parameter(root, "Contact/Point Contact Axes", "string", axes)
    set_parameter(root, "Output/Write VTK", "bool", "false")
    for beam in ("beam 1", "beam 2"):
        set_parameter(root, "Beams/" + beam + "/Elements", "int", str(elements))
    name = "%s_%s_%s_%d" % (example, strategy.replace(" ", "_"), axes, elements)
    deck = os.path.join(work, name + ".xml")
    tree.write(deck)
    out = os.path.join(work, name)
    r = subprocess.run([exe, "run", deck, "-o", out, "-q", "--overwrite"], capture_output=True, text=True)
    if r.returncode != 0:
        return None, (r.stderr.strip().splitlines() or ["exit %d" % r.returncode])[-1]
    with open(os.path.join(out, "tracked_points.csv")) as f:
        last = list(csv.DictReader(f))[-1]
    values = {k: float(last[k]) for k in ("A_ux", "A_uz", "B_ux", "B_uz") if k in last}
    with open(os.path.join(out, "contact_points.csv")) as f:
        rows = [row for row in csv.DictReader(f) if row["step"] == last["step"] and row["active"] == "1"]
    values["N"] = sum(float(row["normal_force"]) for row in rows)
    return values, None


def main():
    exe, work = sys.argv[1:3]
    os.makedirs(work, exist_ok=True)
    for example in ("example1", "example2", "example3"):
        for strategy in STRATEGIES:
            got = {}
            for axes in ("Chord", "Hermite"):
                for n in (10, 20):
                    got[axes, n], failure = run(exe, work, example, strategy, axes, n)
                    if failure:
                        print("%s, %s, %s, %d elements: incomplete: %s" % (example, strategy, axes, n, failure))
            base = got["Chord", 10]
            if base is None:
                continue
            print("\n%s, %s" % (example, strategy))
            print("| quantity | chord 10 | Hermite 10 | Hermite - chord | chord 20 - chord 10 | Hermite 20 - Hermite 10 |")
            print("|---|---|---|---|---|---|")
            for k in base:
                def diff(a, b):
                    if got[a] is None or got[b] is None:
                        return "-"
                    d = got[a][k] - got[b][k]
                    return "%+.4g (%+.2f %%)" % (d, 100 * d / abs(got[b][k])) if got[b][k] else "%+.4g" % d
                h = "%.6g" % got["Hermite", 10][k] if got["Hermite", 10] else "-"
                print("| %s | %.6g | %s | %s | %s | %s |" % (
                    k, base[k], h, diff(("Hermite", 10), ("Chord", 10)), diff(("Chord", 20), ("Chord", 10)),
                    diff(("Hermite", 20), ("Hermite", 10))))


if __name__ == "__main__":
    main()
