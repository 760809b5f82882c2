#!/usr/bin/python3
"""Linear Solver/Direct Solver = Automatic (the default) end to end: the run's header line and
effective_parameters.xml say what was chosen, by the rule the deck reference states ("UMFPACK with
Reuse Factorization from N unknowns ... with a contact point for every K unknowns or fewer,
on several ranks MUMPS with it from M unknowns; KLU2 otherwise", N, K, M read from
--print-valid-parameters; unknowns
= 6 per node from the header's node count, contact points from `beamcontact check`), and an explicit
choice wins.
  - Example 1 (22 nodes) on 1 rank: KLU2 without Reuse Factorization.
  - 3 x 3 crossed layers, 200 elements per beam (1206 nodes, 9 points: nearly banded): KLU2.
  - 16 x 16 crossed layers laid on each other and loaded (576 nodes, 256 points): UMFPACK with Reuse
    Factorization on 1 and on 2 ranks (below M); the same deck naming KLU2: KLU2 without reuse and no
    choice line. The three runs' contact forces agree to 1e-8 of the largest (the solvers differ by
    round-off and GMRES's target, far below the Newton tolerance's effect).
  - 16 x 16 layers 3 apart, pressed 3.4: KLU2 at the start (no point), UMFPACK with Reuse
    Factorization from the step where the points appear (the rule with the points of that moment).
Usage: default_solver.py BEAMCONTACT SOURCE_DIR WORK MPIEXEC...
"""
import csv
import math
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET


def linear_solver(out):
    """(Direct Solver, Reuse Factorization, the Direct Solver's doc string) of effective_parameters.xml."""
    text = open(os.path.join(out, "effective_parameters.xml")).read()
    root = ET.fromstring(text[text.index("<ParameterList"):])
    lin = next(p for p in root.iter("ParameterList") if p.get("name") == "Linear Solver")
    values = {p.get("name"): p for p in lin.findall("Parameter")}
    reuse = values.get("Reuse Factorization")
    return (values["Direct Solver"].get("value"), reuse.get("value") if reuse is not None else None,
            values["Direct Solver"].get("docString", ""))


def run(cmd, out):
    r = subprocess.run(cmd + ["--output", out, "--overwrite"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} exited with {r.returncode}:\n{r.stdout}\n{r.stderr}")
    nodes = int(re.search(r"(\d+) nodes", r.stdout).group(1))
    line = re.search(r"^Direct Solver: (.*)$", r.stdout, re.M)
    return nodes, line.group(1) if line else None


def forces(out):
    with open(os.path.join(out, "contact_points.csv")) as f:
        rows = list(csv.DictReader(f))
    last = rows[-1]["step"]
    return [float(r["normal_force"]) for r in rows if r["step"] == last]


def main():
    exe, source, work, mpi = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    os.makedirs(work, exist_ok=True)
    reference = subprocess.run([exe, "--print-valid-parameters"], capture_output=True, text=True, check=True).stdout
    words = " ".join(reference.split())
    threshold = int(re.search(r"from (\d+) unknowns \(6 per node", words).group(1))
    per_point = int(re.search(r"a contact point for every (\d+) unknowns", words).group(1))
    mumps = int(re.search(r"on several ranks MUMPS with it from (\d+) unknowns", words).group(1))
    print(f"the reference's rule: from {threshold} unknowns with a point per {per_point} unknowns, MUMPS from {mumps}")
    failures = 0

    def expect(what, deck, out, line, nodes, ranks, method, reuse):
        nonlocal failures
        got = linear_solver(out)
        checked = subprocess.run([exe, "check", deck], capture_output=True, text=True, check=True).stdout
        points = int(re.search(r"(\d+) contact points at the start", checked).group(1))
        large = 6 * nodes >= threshold and points * per_point >= 6 * nodes
        rule = ("MUMPS" if ranks > 1 and 6 * nodes >= mumps else "UMFPACK", "true") if large else ("KLU2", "false")
        print(f"{what}: {6 * nodes} unknowns, {points} points on {ranks} rank(s): header {line!r}; effective {got[0]}, reuse {got[1]}")
        ok = got[:2] == (method, reuse)
        if line is not None:  # an automatic choice: by the rule, said in the header and the doc string
            ok = ok and (method, reuse) == rule and line.startswith(method)
            ok = ok and f"{6 * nodes} unknowns" in line and f"{6 * nodes} unknowns" in got[2]
        failures += not ok

    example = os.path.join(source, "input", "example1.xml")
    out = os.path.join(work, "example1")
    nodes, line = run([exe, "run", example], out)
    expect("Example 1", example, out, line, nodes, 1, "KLU2", "false")
    failures += line is None

    def layers(n, elements):
        span = 10.0 * (n + 1)
        load = 0.1 * 384 * 1e5 * math.pi / 4 / (5 * n * span ** 3)
        deck = os.path.join(work, f"layers{n}.xml")
        subprocess.run([exe, "generate", "grid", "--n", str(n), "--m", str(n), "--elements", str(elements), "--gap",
                        "0", "--press", "0", "--friction", "0", "--load", repr(load), "--increments", "2", "--overwrite", "--output",
                        deck], check=True, capture_output=True)
        text = open(deck).read().replace('<ParameterList name="BeamContact">', '<ParameterList name="BeamContact">'
                                         '<ParameterList name="Output"><Parameter name="Write VTK" type="bool" '
                                         'value="false"/></ParameterList>', 1)
        open(deck, "w").write(text)
        return deck, text

    deck, _ = layers(3, 200)
    out = os.path.join(work, "banded")
    nodes, line = run([exe, "run", deck], out)
    failures += 6 * nodes < threshold  # large enough: the points decide
    expect("3x3 layers, 200 elements", deck, out, line, nodes, 1, "KLU2", "false")
    failures += line is None

    deck, text = layers(16, 17)
    explicit = os.path.join(work, "layers_klu2.xml")
    open(explicit, "w").write(text.replace('<ParameterList name="BeamContact">',
                                           '<ParameterList name="BeamContact"><ParameterList name="Linear Solver">'
                                           '<Parameter name="Direct Solver" type="string" value="KLU2"/>'
                                           '</ParameterList>', 1))
    outs = [os.path.join(work, name) for name in ("layers_np1", "layers_np2", "layers_klu2")]
    nodes, line = run([exe, "run", deck], outs[0])
    expect("16x16 layers", deck, outs[0], line, nodes, 1, "UMFPACK", "true")
    nodes, line = run(mpi + [exe, "run", deck], outs[1])
    expect("16x16 layers", deck, outs[1], line, nodes, 2, "UMFPACK", "true")
    nodes, line = run([exe, "run", explicit], outs[2])
    expect("16x16 layers, KLU2 named", explicit, outs[2], line, nodes, 1, "KLU2", "false")
    failures += line is not None
    f = [forces(o) for o in outs]
    scale = max(abs(v) for v in f[2])
    diff = max(abs(a - b) for other in f[:2] for a, b in zip(other, f[2]))
    print(f"contact forces: {len(f[2])} points, largest {scale:.6g}; the automatic runs against KLU2 differ by "
          f"{diff / scale:.1e} of it")
    failures += not (len(f[0]) == len(f[1]) == len(f[2]) > 0 and diff <= 1e-8 * scale)

    # Contact that appears during the run: 16 x 16 layers 3 apart, pressed 3.4. At the start no point
    # (KLU2); once the layers come within the search's reach the rule holds with the points of that
    # moment, and the run changes to UMFPACK with Reuse Factorization, said in a second header line
    # and in effective_parameters.xml with the step; its forces agree with the same deck on KLU2.
    apart = os.path.join(work, "apart.xml")
    subprocess.run([exe, "generate", "grid", "--n", "16", "--m", "16", "--gap", "3", "--press", "3.4", "--friction",
                    "0", "--overwrite", "--output", apart], check=True, capture_output=True)
    text = open(apart).read().replace('<ParameterList name="BeamContact">', '<ParameterList name="BeamContact">'
                                      '<ParameterList name="Output"><Parameter name="Write VTK" type="bool" '
                                      'value="false"/></ParameterList>', 1)
    open(apart, "w").write(text)
    apart_klu2 = os.path.join(work, "apart_klu2.xml")
    open(apart_klu2, "w").write(text.replace('<ParameterList name="BeamContact">',
                                             '<ParameterList name="BeamContact"><ParameterList name="Linear Solver">'
                                             '<Parameter name="Direct Solver" type="string" value="KLU2"/>'
                                             '</ParameterList>', 1))
    out, out_klu2 = os.path.join(work, "apart"), os.path.join(work, "apart_klu2")
    r = subprocess.run([exe, "run", apart, "--output", out, "--overwrite"], capture_output=True, text=True)
    subprocess.run([exe, "run", apart_klu2, "--output", out_klu2, "--overwrite", "-q"], check=True, capture_output=True)
    lines = re.findall(r"^Direct Solver: (.*)$", r.stdout, re.M)
    print(f"layers 3 apart: exit {r.returncode}, header lines {lines}")
    got = linear_solver(out)
    later = re.match(r"UMFPACK with Reuse Factorization \(Automatic: (\d+) unknowns, (\d+) contact points on 1 rank\) "
                     r"from step (\d+) ", lines[1]) if r.returncode == 0 and len(lines) == 2 else None
    ok = later is not None and lines[0].startswith("KLU2") and " 0 contact points" in lines[0]
    if ok:
        unknowns, points, step = map(int, later.groups())
        print(f"  changed at step {step}: {unknowns} unknowns, {points} points; effective {got[0]}, reuse {got[1]}")
        ok = points * per_point >= unknowns >= threshold and got[:2] == ("UMFPACK", "true")
        ok = ok and f"from step {step} " in got[2] and "before it KLU2" in got[2]
        f = forces(out), forces(out_klu2)
        scale = max(abs(v) for v in f[1])
        diff = max(abs(a - b) for a, b in zip(*f))
        print(f"  contact forces against KLU2 throughout: {len(f[0])} points, differ by {diff / scale:.1e} of {scale:.6g}")
        ok = ok and len(f[0]) == len(f[1]) > 0 and diff <= 1e-8 * scale
    failures += not ok

    if failures:
        sys.exit(f"{failures} check(s) failed")
    print("ok")


if __name__ == "__main__":
    main()
