#!/usr/bin/python3
"""A generator's deck (beamcontact generate KIND, 3 x 3) run with each strategy, and with Penalty on 2
ranks. Checks:
  - every run completes;
  - equilibrium at T = 1: the forces the contact points apply on the second family of beams (every
    pair's beam B: the grid's top layer, the weave's wefts; normal and tangential vectors of
    contact_points.csv) balance that family's support reactions, component by component (1e-6 of the
    largest: those beams carry nothing else);
  - the contact pattern is the same for every strategy (the same points active);
  - Lagrange and augmented Lagrange agree (total normal force, 1e-4);
  - 2 ranks give the 1-rank contact rows (1e-8 of the largest value).
Usage: generated_decks.py KIND FAMILY_B_PREFIX BEAMCONTACT WORKDIR MPIEXEC...
"""
import csv
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_gold import set_parameter  # noqa: E402


def rows_at_end(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    last = rows[-1]["step"]
    return [r for r in rows if r["step"] == last]


def run(exe, deck, out, family, mpi=None):
    cmd = (mpi or []) + [exe, "run", deck, "--output", out, "--quiet"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{deck}: exit {r.returncode}: {r.stderr.strip()[-300:]}")
    contact = rows_at_end(os.path.join(out, "contact_points.csv"))
    reactions = rows_at_end(os.path.join(out, "reactions.csv"))[0]
    active = sorted((c["pair"], c["line_A"], c["line_B"]) for c in contact if c["active"] == "1")
    total = sum(float(c["normal_force"]) for c in contact if c["active"] == "1")
    on_b = [sum(float(c["normal_force_" + a]) + float(c["tangential_force_" + a]) for c in contact if c["active"] == "1")
            for a in "xyz"]
    supports = [sum(float(v) for k, v in reactions.items() if k.startswith(family) and k.endswith("_F" + a))
                for a in "xyz"]
    return active, total, (on_b, supports), contact


def main():
    kind, family, exe, work, mpi = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:]
    os.makedirs(work, exist_ok=True)
    base = os.path.join(work, kind + ".xml")
    subprocess.run([exe, "generate", kind, "--n", "3", "--m", "3", "--output", base], check=True)
    results = {}
    failures = 0
    for strategy in ["Penalty", "Lagrange Multiplier", "Augmented Lagrange"]:
        tree = ET.parse(base)
        set_parameter(tree.getroot(), "Contact/Enforcement/Type", "string", strategy)
        set_parameter(tree.getroot(), "Output/Write VTK", "bool", "false")
        deck = os.path.join(work, strategy.replace(" ", "_") + ".xml")
        tree.write(deck)
        active, total, (on_b, supports), contact = run(exe, deck, os.path.join(work, strategy.replace(" ", "_")), family)
        results[strategy] = (active, total, contact)
        scale = max(abs(v) for v in supports)
        balance = max(abs(a + b) for a, b in zip(on_b, supports)) / scale
        print(f"{strategy:20s} {len(active)} active points, total N {total:.6f}; on the {family} beams: contact "
              f"({', '.join(f'{v:.6f}' for v in on_b)}), supports ({', '.join(f'{v:.6f}' for v in supports)}), "
              f"balance {balance:.1e}")
        failures += not (balance < 1e-6)
        if strategy == "Penalty":
            _, total2, _, contact2 = run(exe, deck, os.path.join(work, "penalty_np2"), family, mpi)
            scale = max(abs(float(v)) for c in contact for k, v in c.items() if k.startswith("normal_force"))
            diff = max(abs(float(a[k]) - float(b[k])) for a, b in zip(contact, contact2)
                       for k in a if k.startswith("normal_force") or k.startswith("tangential_force"))
            print(f"Penalty on 2 ranks: total N {total2:.6f}, max difference of the contact rows / scale {diff / scale:.1e}")
            failures += not (len(contact) == len(contact2) and diff <= 1e-8 * scale)
    patterns = {s: r[0] for s, r in results.items()}
    if len(set(map(tuple, patterns.values()))) != 1:
        print("contact patterns differ:", patterns)
        failures += 1
    nl, na = results["Lagrange Multiplier"][1], results["Augmented Lagrange"][1]
    print(f"Lagrange vs augmented Lagrange: {abs(nl - na) / nl:.1e}")
    failures += not (abs(nl - na) <= 1e-4 * nl)
    if failures:
        sys.exit(f"{failures} check(s) failed")
    print("ok")


if __name__ == "__main__":
    main()
