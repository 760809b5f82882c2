#!/usr/bin/python3
"""The seed paper's Examples 1-3 against 3D solid models in CalculiX (ccx, Debian's calculix-ccx).

    calculix_examples.py BEAMCONTACT WORKDIR [--example N ...] [--mesh 1,2] [--penalty 1e5,1e6]
                         [--friction on|off|both] [--surfaces sides,top,swap] [--quick] [--ccx ccx]

For each example and friction setting it writes a CalculiX deck of the two beams as 3D solids, runs
ccx (1 thread) at each mesh level and penalty stiffness, runs our beam model on the deck
(input/exampleN.xml, Lagrange multiplier; with friction both the deck's "Per Line" law and
"Isotropic Coulomb", which is the law of the solid), and prints every component the deck tracks at
T = 1 (tracked points' displacements, the supports' reactions, the contact force) with the relative
differences ours vs the finest solid. It also prints the solid's contact patch at T = 1: its extent,
the pressure centroid in beam 1's section and in beam 2's, and the contact force resultant and its
moment about beam 1's axis (torsion put into beam 1), against our active contact points.

The solid models (units as in the decks):
- Rectangular boxes, C3D20R (20-node reduced-integration hexahedra), beam 1 10 x 10 x 100 along X,
  beam 2 5 x 5 x 100 along Y, positions, materials (linear elastic, St. Venant-Kirchhoff with NLGEOM)
  as in the decks. Mesh level m: 2m elements through each side of each section; along the beams
  cubes of the section's element size in a window around the contact path (beam 1) and the
  crossing (beam 2), graded to about a section size outside.
- Supports: every supported beam end (clamp or driven node of the deck) is an end face made a rigid
  body (*RIGID BODY) whose reference node and rotation node carry the deck's fixed / prescribed
  components of that node: kinematically the beam model's rigid section at a node, the same
  constraints. Example 1's node B (u_Y, r_X, r_Z held at the centre of beam 2) is u_Y = 0 on every
  node of beam 2's centre section (the section stays in the symmetry plane: it cannot move along Y
  nor turn about X or Z), free otherwise.
- Loading: the decks' prescribed displacements ramped linearly in one NLGEOM static step, increments
  at most 1/(the deck's increment count).
- Contact: surface-to-surface penalty (PRESSURE-OVERCLOSURE=LINEAR, slope K, force/length^3), slave
  beam 2's bottom and side faces near the crossing, master beam 1's top and side faces along the
  contact path ("s" in the tables); or, to show how much the edges' treatment matters (on the
  coarsest mesh), beam 2's bottom face against beam 1's top face only ("t"), or the "s" faces with
  beam 1 as slave and beam 2 as master ("w": the contact normal is beam 2's face normal); Coulomb friction at the deck's coefficient with stick slope (tangential penalty,
  force/length^3) equal to K, or none. (A stick slope of K / 50 leaves the friction short of mu N:
  Example 2, level 1, K = 1e6: A u_X -0.2299 with K / 50, -0.2366 with K / 5, -0.2373 with K.)
Tracked points: A (beam 1's free end) is the centre node of the end face; B (Example 1) the centre
node of beam 2's centre section; C (Examples 2, 3) the driven rigid end's reference node.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "cli"))
from check_gold import set_parameter  # noqa: E402  (edits a deck by parameter path)

# The decks' data (input/exampleN.xml), restated for the solid: beam 2's centre height z0, its x,
# the prescribed end motion at T = 1, the increments, the friction coefficient, the materials, and
# the window of beam 1 (x range) that the contact visits (from our runs, with a margin).
EXAMPLES = {
    1: dict(x2=50.0, z0=8.0, u=(40.0, 0.0, -20.0), incs=50, mu=0.5, E2=30000.0, nu2=0.17,
            both_ends=True, window=(42.0, 98.0)),
    2: dict(x2=50.0, z0=8.9, u=(30.0, 0.0, -25.0), incs=40, mu=1.0, E2=20000.0, nu2=0.3,
            both_ends=False, window=(40.0, 72.0)),
    3: dict(x2=90.0, z0=7.65, u=(-30.0, 0.0, -20.0), incs=40, mu=1.0, E2=20000.0, nu2=0.3,
            both_ends=False, window=(66.0, 100.0)),
}
E1, NU1 = 30000.0, 0.17


def grid(lo, hi, fine_lo, fine_hi, h_fine, h_coarse, must=()):
    """1D node positions on [lo, hi]: size h_fine on [fine_lo, fine_hi], graded (x1.5 per element)
    to at most h_coarse outside; every value of `must` is a node."""
    fine_lo, fine_hi = max(lo, fine_lo), min(hi, fine_hi)
    n = max(1, round((fine_hi - fine_lo) / h_fine))
    pts = list(np.linspace(fine_lo, fine_hi, n + 1))

    def grade(start, end):  # from start (fine) to end, growing sizes
        out, x, h, sgn = [], start, h_fine, 1.0 if end > start else -1.0
        while abs(end - x) > 1e-9:
            h = min(h * 1.5, h_coarse)
            if abs(end - x) < 1.5 * h:
                h = abs(end - x)
            x += sgn * h
            out.append(x)
        return out

    pts = grade(fine_lo, lo)[::-1] + pts + grade(fine_hi, hi)
    pts = sorted(set(round(p, 9) for p in pts) | set(must))
    clean = [pts[0]]
    for p in pts[1:]:
        if p - clean[-1] > 0.2 * h_fine or p in must:
            if p - clean[-1] <= 0.2 * h_fine:
                clean.pop()
            clean.append(p)
    return clean


class Mesh:
    """Structured C3D20R boxes, global axes as element axes (xi = X, eta = Y, zeta = Z)."""

    def __init__(self):
        self.nodes = {}  # id -> (x, y, z)
        self.elems = []  # (id, [20 node ids])
        self.next_node, self.next_elem = 1, 1

    def box(self, xs, ys, zs):
        """Returns a dict with the box's node-id array (on the doubled grid, -1 where no node),
        its elements (index -> id) and the grids."""
        def doubled(v):
            out = []
            for a, b in zip(v[:-1], v[1:]):
                out += [a, 0.5 * (a + b)]
            return out + [v[-1]]
        X, Y, Z = doubled(xs), doubled(ys), doubled(zs)
        ids = -np.ones((len(X), len(Y), len(Z)), dtype=int)
        for i, x in enumerate(X):
            for j, y in enumerate(Y):
                for k, z in enumerate(Z):
                    if (i % 2) + (j % 2) + (k % 2) <= 1:
                        ids[i, j, k] = self.next_node
                        self.nodes[self.next_node] = (x, y, z)
                        self.next_node += 1
        el = {}
        for a in range(len(xs) - 1):
            for b in range(len(ys) - 1):
                for c in range(len(zs) - 1):
                    i, j, k = 2 * a, 2 * b, 2 * c
                    n = lambda di, dj, dk: int(ids[i + di, j + dj, k + dk])  # noqa: E731
                    conn = [n(0, 0, 0), n(2, 0, 0), n(2, 2, 0), n(0, 2, 0), n(0, 0, 2), n(2, 0, 2), n(2, 2, 2),
                            n(0, 2, 2), n(1, 0, 0), n(2, 1, 0), n(1, 2, 0), n(0, 1, 0), n(1, 0, 2), n(2, 1, 2),
                            n(1, 2, 2), n(0, 1, 2), n(0, 0, 1), n(2, 0, 1), n(2, 2, 1), n(0, 2, 1)]
                    self.elems.append((self.next_elem, conn))
                    el[(a, b, c)] = self.next_elem
                    self.next_elem += 1
        return dict(ids=ids, el=el, xs=xs, ys=ys, zs=zs, X=X, Y=Y, Z=Z)


def lines(items, per=8):
    items = [str(i) for i in items]
    return "\n".join(", ".join(items[i:i + per]) for i in range(0, len(items), per))


def write_deck(path, ex, level, K, friction, stick=1.0, surf="s"):
    sides = surf != "t"
    d = EXAMPLES[ex]
    m = Mesh()
    n = 2 * level
    h1, h2 = 10.0 / n, 5.0 / n
    # beam 1: x along the beam, y, z across (10 x 10 centred on the X axis)
    b1 = m.box(grid(0.0, 100.0, d["window"][0], d["window"][1], h1, 10.0, must=(0.0, 100.0)),
               list(np.linspace(-5, 5, n + 1)), list(np.linspace(-5, 5, n + 1)))
    x2, z0 = d["x2"], d["z0"]
    b2 = m.box(list(np.linspace(x2 - 2.5, x2 + 2.5, n + 1)),
               grid(-50.0, 50.0, -15.0, 15.0, h2, 5.0, must=(-50.0, 0.0, 50.0)),
               list(np.linspace(z0 - 2.5, z0 + 2.5, n + 1)))
    ref = {}
    for name in ("r1", "q1", "r2", "q2", "r3", "q3"):
        ref[name] = m.next_node
        m.next_node += 1
    ref_pos = {"r1": (0.0, 0.0, 0.0), "r2": (x2, -50.0, z0), "r3": (x2, 50.0, z0)}
    for r, p in ref_pos.items():
        m.nodes[ref[r]] = p
        m.nodes[ref["q" + r[1]]] = p

    def face_nodes(b, axis, idx):
        ids = b["ids"]
        sl = [slice(None)] * 3
        sl[axis] = idx
        return [int(v) for v in ids[tuple(sl)].ravel() if v > 0]

    def centre(b, axis, idx):
        ids = b["ids"]
        c = [ids.shape[0] // 2, ids.shape[1] // 2, ids.shape[2] // 2]
        c[axis] = idx
        return int(ids[tuple(c)])

    out = ["*HEADING", "Seed paper Example %d, 3D solid, mesh level %d, K %g, friction %s" % (ex, level, K, friction),
           "*NODE"]
    out += ["%d, %.10g, %.10g, %.10g" % (i, *p) for i, p in sorted(m.nodes.items())]
    el1 = [e for e in b1["el"].values()]
    el2 = [e for e in b2["el"].values()]
    conn = dict(m.elems)
    out.append("*ELEMENT, TYPE=C3D20R, ELSET=BEAM1")
    for e in el1:
        out.append("%d, %s,\n%s" % (e, ", ".join(map(str, conn[e][:15])), ", ".join(map(str, conn[e][15:]))))
    out.append("*ELEMENT, TYPE=C3D20R, ELSET=BEAM2")
    for e in el2:
        out.append("%d, %s,\n%s" % (e, ", ".join(map(str, conn[e][:15])), ", ".join(map(str, conn[e][15:]))))
    sets = {"END1": face_nodes(b1, 0, 0), "TIP1": face_nodes(b1, 0, -1), "END2S": face_nodes(b2, 1, 0),
            "END2E": face_nodes(b2, 1, -1)}
    mid2 = list(b2["Y"]).index(0.0)
    sets["MID2"] = face_nodes(b2, 1, mid2)
    tracked = {"A": centre(b1, 0, -1), "B": centre(b2, 1, mid2)}
    for s, ns in sets.items():
        out += ["*NSET, NSET=%s" % s, lines(ns)]
    out += ["*NSET, NSET=TRACK", lines(sorted(set(tracked.values()) | {ref["r1"], ref["r2"], ref["r3"]}))]
    out += ["*NSET, NSET=ROTS", lines([ref["q1"], ref["q2"], ref["q3"]])]
    # contact surfaces: master beam 1 top (S2) and y-sides (S3 at y-, S5 at y+) in the window; slave
    # beam 2 bottom (S1) and x-sides (S6 at x-, S4 at x+) in |y| <= 15
    nx1, ny1, nz1 = len(b1["xs"]) - 1, len(b1["ys"]) - 1, len(b1["zs"]) - 1
    master = []
    for a in range(nx1):
        xa, xb = b1["xs"][a], b1["xs"][a + 1]
        if xb < d["window"][0] - 1e-9 or xa > d["window"][1] + 1e-9:
            continue
        for b in range(ny1):
            master.append((b1["el"][(a, b, nz1 - 1)], "S2"))
        for c in range(nz1 if sides else 0):
            master.append((b1["el"][(a, 0, c)], "S3"))
            master.append((b1["el"][(a, ny1 - 1, c)], "S5"))
    nx2, ny2, nz2 = len(b2["xs"]) - 1, len(b2["ys"]) - 1, len(b2["zs"]) - 1
    slave = []
    for b in range(ny2):
        ya, yb = b2["ys"][b], b2["ys"][b + 1]
        if yb < -15.0 - 1e-9 or ya > 15.0 + 1e-9:
            continue
        for a in range(nx2):
            slave.append((b2["el"][(a, b, 0)], "S1"))
        for c in range(nz2 if sides else 0):
            slave.append((b2["el"][(0, b, c)], "S6"))
            slave.append((b2["el"][(nx2 - 1, b, c)], "S4"))
    if surf == "w":  # beam 1's faces slave, beam 2's master (normals of beam 2's faces)
        master, slave = slave, master
    out.append("*SURFACE, NAME=MASTER, TYPE=ELEMENT")
    out += ["%d, %s" % f for f in master]
    out.append("*SURFACE, NAME=SLAVE, TYPE=ELEMENT")
    out += ["%d, %s" % f for f in slave]
    out += ["*MATERIAL, NAME=M1", "*ELASTIC", "%g, %g" % (E1, NU1),
            "*MATERIAL, NAME=M2", "*ELASTIC", "%g, %g" % (d["E2"], d["nu2"]),
            "*SOLID SECTION, ELSET=BEAM1, MATERIAL=M1", "*SOLID SECTION, ELSET=BEAM2, MATERIAL=M2"]
    out += ["*RIGID BODY, NSET=END1, REF NODE=%d, ROT NODE=%d" % (ref["r1"], ref["q1"])]
    out += ["*RIGID BODY, NSET=END2E, REF NODE=%d, ROT NODE=%d" % (ref["r3"], ref["q3"])]
    out += ["*RIGID BODY, NSET=END2S, REF NODE=%d, ROT NODE=%d" % (ref["r2"], ref["q2"])]
    out += ["*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", "%g" % K]
    if friction:
        out += ["*FRICTION", "%g, %g" % (d["mu"], K / stick)]
    out += ["*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SLAVE, MASTER"]
    # supports: beam 1 clamped; Example 1: beam 2's ends driven (u_Y free, r_Y held, r_X r_Z free) and
    # B's section held in u_Y; Examples 2, 3: beam 2's start clamped, end driven in X and Z
    out += ["*BOUNDARY", "%d, 1, 3" % ref["r1"], "%d, 1, 3" % ref["q1"]]
    ux, _, uz = d["u"]
    if d["both_ends"]:
        for r, q in (("r2", "q2"), ("r3", "q3")):
            out += ["%d, 2, 2" % ref[q]]
        out += ["MID2, 2, 2"]
    else:
        out += ["%d, 1, 3" % ref["r2"], "%d, 1, 3" % ref["q2"]]
    inc = 1.0 / d["incs"]
    out += ["*STEP, NLGEOM, INC=10000", "*STATIC", "%g, 1.0, %g, %g" % (inc, inc * 1e-4, inc), "*BOUNDARY"]
    driven = ("r2", "r3") if d["both_ends"] else ("r3",)
    for r in driven:
        out += ["%d, 1, 1, %g" % (ref[r], ux), "%d, 3, 3, %g" % (ref[r], uz)]
    out += ["*NODE PRINT, NSET=TRACK", "U, RF", "*NODE PRINT, NSET=ROTS", "U, RF",
            "*NODE FILE, OUTPUT=3D", "U", "*CONTACT FILE", "CDIS, CSTR", "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    info = dict(tracked=tracked, ref=ref, slave=slave, slave_is_beam1=surf == "w", conn=conn, nodes=m.nodes, nodes_count=len(m.nodes),
                elements=len(m.elems))
    return info


def read_dat_last(path):
    """The last increment's blocks of the .dat file: {title: [[numbers]...]} with the time."""
    blocks, cur, t = {}, None, None
    with open(path) as f:
        for line in f:
            s = line.strip()
            mt = re.search(r"^(.*?)\s+and time\s+([0-9.E+-]+)", s)
            if mt:
                tt = float(mt.group(2))
                if t is None or tt > t + 1e-12:
                    blocks, t = {}, tt
                cur = mt.group(1).strip()
                blocks[cur] = []
                continue
            if cur and s:
                try:
                    blocks[cur].append([float(v) for v in s.split()])
                except ValueError:
                    pass
    return blocks, t


def read_frd_last(path):
    """The last step's DISP and CONTACT nodal results of an ASCII .frd: {block: {node: values}}."""
    res, cur, data = {}, None, None
    with open(path) as f:
        for line in f:
            if line.startswith(" -4"):
                cur = line[5:13].strip()
                data = {}
                res[cur] = data
            elif line.startswith(" -1") and cur is not None:
                node = int(line[3:13])
                vals = [float(line[13 + 12 * i:25 + 12 * i]) for i in range((len(line.rstrip()) - 13) // 12)]
                data[node] = vals
            elif line.startswith(" -3"):
                cur = None
    return res


def patch(info, frd, F):
    """The solid's contact patch at T = 1 from the slave's nodal values: the nodes in contact
    (pressure > 0), their extent and pressure-weighted centroid (deformed), the mean deformed normal
    of the slave faces in contact (pressure-weighted), and the total contact force F on beam 2 (the
    reaction of beam 1's clamp) split into normal N = F.n and tangential |F - N n| along that normal."""
    cont, disp = frd.get("CONTACT", {}), frd.get("DISP", {})
    faces = {"S1": [1, 4, 3, 2], "S2": [5, 6, 7, 8], "S3": [1, 2, 6, 5], "S4": [2, 3, 7, 6], "S5": [3, 4, 8, 7],
             "S6": [4, 1, 5, 8]}  # corner nodes, outward normal by the right-hand rule

    def pos(k):
        return np.array(info["nodes"][k]) + np.array(disp.get(k, [0, 0, 0])[:3])

    nsum, pts, ws = np.zeros(3), [], []
    for e, fname in info["slave"]:
        cs = [info["conn"][e][k - 1] for k in faces[fname]]
        allnodes = set(cs)
        press = [max(0.0, cont.get(k, [0] * 6)[3]) for k in allnodes]
        if max(press) <= 0:
            continue
        X = [pos(k) for k in cs]
        nrm = np.cross(X[2] - X[0], X[3] - X[1])
        nsum += sum(press) * nrm / np.linalg.norm(nrm)
    for k in {info["conn"][e][i] for e, _ in info["slave"] for i in range(20)}:
        p = cont.get(k, [0] * 6)[3]
        if p > 0:
            pts.append(pos(k))
            ws.append(p)
    if not pts:
        return None
    pts, ws = np.array(pts), np.array(ws)
    # n onto beam 2: minus beam 2's outward normal, or beam 1's outward normal if beam 1 is the slave
    n = (1.0 if info["slave_is_beam1"] else -1.0) * nsum / np.linalg.norm(nsum)
    F = np.array(F)
    N = float(F @ n)
    T = F - N * n
    return dict(n=n, N=N, T=float(np.linalg.norm(T)), Tvec=T, nodes=len(pts), centroid=ws @ pts / ws.sum(),
                lo=pts.min(axis=0), hi=pts.max(axis=0), pen=max(-cont[k][0] for k in cont if cont[k][3] > 0))


def run_solid(work, ex, level, K, friction, ccx, stick=1.0, surf="s"):
    name = "ex%d_m%d_K%g_%s%s" % (ex, level, K, "mu_s%g" % stick if friction else "nomu",
                                  {"s": "", "t": "_top", "w": "_swap"}[surf])
    deck = os.path.join(work, name + ".inp")
    info = write_deck(deck, ex, level, K, friction, stick, surf)
    t0 = time.time()
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1")
    if not os.path.exists(os.path.join(work, name + ".done")):
        r = subprocess.run([ccx, "-i", name], cwd=work, env=env, capture_output=True, text=True)
        with open(os.path.join(work, name + ".log"), "w") as f:
            f.write(r.stdout + r.stderr)
        if r.returncode != 0 or "Job finished" not in r.stdout:
            return dict(error=(r.stdout.strip().splitlines() or ["exit %d" % r.returncode])[-1], name=name)
        open(os.path.join(work, name + ".done"), "w").write("%.1f\n" % (time.time() - t0))
    secs = float(open(os.path.join(work, name + ".done")).read())
    blocks, t = read_dat_last(os.path.join(work, name + ".dat"))
    if t is None or abs(t - 1.0) > 1e-6:
        return dict(error="stopped at T = %s" % t, name=name)
    u = {int(r[0]): r[1:4] for r in blocks.get("displacements (vx,vy,vz) for set TRACK", [])}
    rf = {int(r[0]): r[1:4] for r in blocks.get("forces (fx,fy,fz) for set TRACK", [])}
    rfq = {int(r[0]): r[1:4] for r in blocks.get("forces (fx,fy,fz) for set ROTS", [])}
    ref, tr = info["ref"], info["tracked"]
    v = {}
    for i, c in enumerate("xyz"):
        v["A_u" + c] = u[tr["A"]][i]
        if ex == 1:
            v["B_u" + c] = u[tr["B"]][i]
        else:
            v["C_u" + c] = u[ref["r3"]][i]
    sup = [("clamp of beam 1", "r1", "q1")]
    if ex == 1:
        sup += [("beam 2 start", "r2", "q2"), ("beam 2 end", "r3", "q3")]
    else:
        sup += [("clamp of beam 2", "r2", "q2"), ("free end of beam 2", "r3", "q3")]
    for s, r, q in sup:
        for i, c in enumerate("xyz"):
            v["%s_F%s" % (s, c)] = rf[ref[r]][i]
        for i, c in enumerate("xyz"):
            v["%s_M%s" % (s, c)] = rfq[ref[q]][i]
    v["contact force |F|"] = float(np.linalg.norm([v["clamp of beam 1_F" + c] for c in "xyz"]))
    frd = read_frd_last(os.path.join(work, name + ".frd"))
    # the contact force on beam 2 is the clamp of beam 1's reaction (beam 1 carries nothing else)
    v["_patch"] = patch(info, frd, [v["clamp of beam 1_F" + c] for c in "xyz"])
    v["_secs"] = secs
    v["_size"] = (info["nodes_count"], info["elements"])
    return v


def run_ours(exe, work, ex, law, friction):
    tree = ET.parse(os.path.join(HERE, "..", "input", "example%d.xml" % ex))
    root = tree.getroot()
    set_parameter(root, "Contact/Enforcement/Type", "string", "Lagrange Multiplier")
    set_parameter(root, "Output/Write VTK", "bool", "false")
    if friction:
        set_parameter(root, "Contact/Friction Law", "string", law)
    else:
        set_parameter(root, "Contact/Pairs/crossing/Friction Coefficient", "double", "0.0")
    name = "ours_ex%d_%s" % (ex, law.replace(" ", "_") if friction else "nomu")
    deck = os.path.join(work, name + ".xml")
    tree.write(deck)
    out = os.path.join(work, name)
    r = subprocess.run([exe, "run", deck, "-o", out, "-q", "--overwrite"], capture_output=True, text=True)
    if r.returncode != 0:
        return dict(error=(r.stderr.strip().splitlines() or ["exit %d" % r.returncode])[-1])
    v = {}
    with open(os.path.join(out, "tracked_points.csv")) as f:
        last = list(csv.DictReader(f))[-1]
    for k, x in last.items():
        if re.match(r"^[ABC]_u[xyz]$", k):
            v[k] = float(x)
    with open(os.path.join(out, "reactions.csv")) as f:
        last = list(csv.DictReader(f))[-1]
    for k, x in last.items():
        if k not in ("step", "T"):
            v[k] = float(x)
    v["contact force |F|"] = float(np.linalg.norm([v["clamp of beam 1_F" + c] for c in "xyz"]))
    pts = []
    with open(os.path.join(out, "contact_points.csv")) as f:
        rows = list(csv.DictReader(f))
    step = rows[-1]["step"]
    for r in rows:
        if r["step"] == step and r["active"] == "1":
            pts.append(r)
    v["_points"] = pts
    return v


def fmt(x):
    return "%11.4g" % x if isinstance(x, float) else "%11s" % x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("beamcontact")
    ap.add_argument("work")
    ap.add_argument("--example", type=int, action="append", choices=(1, 2, 3))
    ap.add_argument("--mesh", default="1,2", help="mesh levels (2m elements through a section side)")
    ap.add_argument("--penalty", default="1e5,1e6", help="contact stiffnesses K (force/length^3)")
    ap.add_argument("--friction", default="both", choices=("on", "off", "both"))
    ap.add_argument("--quick", action="store_true", help="coarsest mesh, first penalty, variant s, Example 2 only")
    ap.add_argument("--surfaces", default="sides,top,swap",
                    help="contact surfaces: sides (top and side faces, all levels), top (top / bottom faces only), swap "
                         "(beam 2 master; top and swap on the coarsest level and the largest K)")
    ap.add_argument("--ccx", default="ccx")
    a = ap.parse_args()
    examples = a.example or ([2] if a.quick else [1, 2, 3])
    levels = [int(s) for s in a.mesh.split(",")]
    Ks = [float(s) for s in a.penalty.split(",")]
    if a.quick:
        levels, Ks = levels[:1], Ks[:1]
    fr = {"on": [True], "off": [False], "both": [False, True]}[a.friction]
    os.makedirs(a.work, exist_ok=True)
    ver = subprocess.run([a.ccx, "-v"], capture_output=True, text=True).stdout.strip().splitlines()
    print("ccx: %s; mesh levels %s, K %s" % (ver[-1] if ver else "?", levels, Ks))
    for ex in examples:
        for friction in fr:
            ours = {"Per Line": run_ours(a.beamcontact, a.work, ex, "Per Line", friction)}
            if friction:
                ours["Isotropic Coulomb"] = run_ours(a.beamcontact, a.work, ex, "Isotropic Coulomb", friction)
            solids = []
            # mesh convergence at the largest K, penalty convergence on the coarsest mesh
            surf = ["sides"] if a.quick else a.surfaces.split(",")
            runs = []
            if "sides" in surf:
                runs += [(lv, Ks[-1], "s") for lv in levels] + [(levels[0], K, "s") for K in Ks[:-1]]
            if "top" in surf:
                runs += [(levels[0], Ks[-1], "t")]
            if "swap" in surf:
                runs += [(levels[0], Ks[-1], "w")]
            for lv, K, sf in runs:
                s = run_solid(a.work, ex, lv, K, friction, a.ccx, surf=sf)
                solids.append(((lv, K, sf), s))
                print("  solid ex%d m%d K%g %s %s: %s" % (ex, lv, K, sf, "mu" if friction else "mu=0",
                      s.get("error") or "%d nodes, %d elements, %.0f s" % (s["_size"] + (s["_secs"],))),
                      flush=True)
            print("\nExample %d, %s, T = 1" % (ex, "friction mu = %g" % EXAMPLES[ex]["mu"] if friction
                                                 else "frictionless"))
            heads = ["%s" % k for k in ours] + ["m%d K%g %s" % key for key, _ in solids]
            print("%-28s" % "component" + "".join("%12s" % h[:11] for h in heads) + "".join(
                "%12s" % ("d " + k[:4]) for k in ours))
            # the reference: the finest mesh that completed at the largest K (first surface variant)
            first = [s for key, s in solids[:len(levels) if "sides" in surf else 1] if "error" not in s]
            ref = first[-1] if first else None
            keys = [k for k in ours["Per Line"] if not k.startswith("_")] if "error" not in ours["Per Line"] else []
            for k in keys:
                row = [o.get(k, float("nan")) for o in ours.values()]
                row += [s.get(k, float("nan")) if "error" not in s else "x" for _, s in solids]
                vals = "".join("%12.5g" % x if isinstance(x, float) else "%12s" % x for x in row)
                diffs = ""
                # a relative difference where the solid's value is not round-off of a zero
                floor = 1e-3 if "_u" in k else (1.0 if "_F" in k else 20.0)
                for o in ours.values():
                    r = ref.get(k) if ref else None
                    if r is None or abs(r) < floor or k not in o:
                        diffs += "%12s" % "-"
                    else:
                        diffs += "%11.1f%%" % (100 * (o[k] - r) / abs(r))
                print("%-28s%s%s" % (k[:28], vals, diffs))
            for key, s in solids:
                p = s.get("_patch") if "error" not in s else None
                if p:
                    print("  solid m%d K%g %s: N %.1f, T %.1f (T/N %.3f), T dir (%.3f, %.3f, %.3f), normal (%.3f, %.3f, "
                          "%.3f), %d nodes in contact, largest penetration %.2g, pressure centroid (%.2f, %.2f, %.2f), "
                          "extent x %.2f..%.2f y %.2f..%.2f z %.2f..%.2f" % (
                              key + (p["N"], p["T"], p["T"] / p["N"], *(p["Tvec"] / max(p["T"], 1e-12)), *p["n"],
                                     p["nodes"], p["pen"], *p["centroid"], p["lo"][0], p["hi"][0], p["lo"][1],
                                     p["hi"][1], p["lo"][2], p["hi"][2])))
            for law, o in ours.items():
                pts = o.get("_points", [])
                if not pts:
                    continue
                N = sum(float(r["normal_force"]) for r in pts)
                Tv = sum(np.array([float(r["tangential_force_" + c]) for c in "xyz"]) for r in pts)
                T = float(np.linalg.norm(Tv))
                print("  ours %s: N %.1f, T %.1f (T/N %.3f), T dir (%.3f, %.3f, %.3f)" % (
                    law, N, T, T / N, *(Tv / max(T, 1e-12))))
                for r in pts:
                    print("    point (%.2f, %.2f, %.2f) lines %s/%s normal (%.3f, %.3f, %.3f) N %.1f T %.1f (%s, %s)" % (
                        float(r["x"]), float(r["y"]), float(r["z"]), r["line_A"], r["line_B"], float(r["normal_x"]),
                        float(r["normal_y"]), float(r["normal_z"]), float(r["normal_force"]),
                        float(r["tangential_force"]), r["state_1"], r["state_2"]))
            print(flush=True)


if __name__ == "__main__":
    main()
