#!/usr/bin/python3
"""Runs a deck with each strategy of its gold file and compares the results with the gold values.

    check_gold.py BEAMCONTACT DECK GOLD WORKDIR

GOLD is a CSV file beside the deck (input/example2.gold for input/example2.xml):
    strategy,quantity,value,tolerance,source
one row per strategy and quantity; `quantity` is a column of tracked_points.csv (e.g. A_uz) or a sum
over the active contact points of contact_points.csv (normal_force, tangential_force), both at the
last step; `tolerance` is relative. The deck is edited by parameter path (Contact/Enforcement/Type,
Output/Write VTK), never as text. Exit 1 when any value is off or any run incomplete.
"""
import csv
import os
import subprocess
import sys
import xml.etree.ElementTree as ET


def set_parameter(root, path, ptype, value):
    """Sets the parameter at `path` ("A/B/name") under the deck's top list, creating sublists."""
    *lists, name = path.split("/")
    node = root
    for sub in lists:
        found = [c for c in node.findall("ParameterList") if c.get("name") == sub]
        node = found[0] if found else ET.SubElement(node, "ParameterList", name=sub)
    found = [c for c in node.findall("Parameter") if c.get("name") == name]
    p = found[0] if found else ET.SubElement(node, "Parameter", name=name)
    p.set("type", ptype)
    p.set("value", value)


def last_row(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return rows[-1] if rows else None


def contact_sums(path, step):
    sums = {"normal_force": 0.0, "tangential_force": 0.0}
    with open(path) as f:
        for r in csv.DictReader(f):
            if r["step"] == step and r["active"] == "1":
                sums["normal_force"] += float(r["normal_force"])
                sums["tangential_force"] += float(r["tangential_force"])
    return sums


def main():
    exe, deck, gold_path, work = sys.argv[1:5]
    with open(gold_path) as f:
        gold = [r for r in csv.DictReader(row for row in f if not row.startswith("#"))]
    strategies = list(dict.fromkeys(r["strategy"] for r in gold))
    failures = 0
    os.makedirs(work, exist_ok=True)
    for strategy in strategies:
        tree = ET.parse(deck)
        set_parameter(tree.getroot(), "Contact/Enforcement/Type", "string", strategy)
        set_parameter(tree.getroot(), "Output/Write VTK", "bool", "false")
        name = strategy.replace(" ", "_")
        case_deck = os.path.join(work, name + ".xml")
        out = os.path.join(work, name)
        tree.write(case_deck)
        r = subprocess.run([exe, "run", case_deck, "--output", out, "--quiet"], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"{strategy}: run failed (exit {r.returncode}): {r.stderr.strip()}")
            failures += 1
            continue
        tracked = last_row(os.path.join(out, "tracked_points.csv"))
        values = dict(tracked)
        values.update(contact_sums(os.path.join(out, "contact_points.csv"), tracked["step"]))
        for g in (g for g in gold if g["strategy"] == strategy):
            got, want, tol = float(values[g["quantity"]]), float(g["value"]), float(g["tolerance"])
            error = abs(got - want) / max(abs(want), 1e-300)
            ok = error <= tol
            failures += not ok
            print(f"{'ok ' if ok else 'OFF'} {strategy:20s} {g['quantity']:16s} {got:16.9g} gold {want:16.9g} "
                  f"relative error {error:.1e} (tolerance {tol:g})")
    if failures:
        sys.exit(f"{failures} value(s) off their gold or runs failed ({gold_path})")


if __name__ == "__main__":
    main()
