#!/usr/bin/python3
"""Pictures of a run's deformation: the beams with their real cross-sections and the contact forces,
at the stages of loading asked (by default four, as in the seed paper's Figs. 4, 6 and 11), from the
run's VTK files.

    /usr/bin/python3 drivers/render_stages.py RESULTS_DIR OUT.png [--stages 0.25,0.5,0.75,1]
                                              [--view ELEVATION,AZIMUTH] [--title TEXT]

Reads results.pvd (the beams) and contact.pvd (the contact points; older results: vertex cells in the
beams' files) and, for each stage, the step whose load factor T is nearest, with VTK's XML reader
(python3-vtk9, or python3-paraview's vtk module; a missing module is one line naming its Debian
package, exit 4); draws the faces of every beam cell (hexahedra for rectangles, wedges for circles)
with matplotlib and each active contact point's force (on beam B) as an arrow scaled to the largest
force of the run's stages. One panel per stage (1 -> 1 x 1, 2 -> 1 x 2, 3 -> 1 x 3, 4 -> 2 x 2,
5 and 6 -> 2 x 3, ...), 200 dpi, titled with the deck's file name (from the run's status.txt; for a
study's case, the study's title and the case number) unless --title is given; the axes are in the model's units, which the decks do not state.
"""
import argparse
import json
import math
import os
import shlex
import sys
import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from python_modules import need as need_module  # noqa: E402
import figure_style  # noqa: E402


def need(module):
    return need_module(module, "render")


np = need("numpy")
matplotlib = need("matplotlib")
matplotlib.use("Agg")
figure_style.setup(matplotlib)
plt = need("matplotlib.pyplot")
vtk = need("vtk")
Poly3DCollection = need("mpl_toolkits.mplot3d.art3d").Poly3DCollection
vtk_to_numpy = need("vtk.util.numpy_support").vtk_to_numpy

COLOURS = ["#8fb3d9", "#e3a16f", "#9fcf8f", "#d98fb3", "#c9c36a"]
PANEL = (5.2, 4.6)  # inches per stage


def read(path, contact_path=None):
    faces, contacts, points = read_grid(path)
    if contact_path is not None:
        contacts += read_grid(contact_path)[1]
    return faces, contacts, points


def read_grid(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    # The files hold the reference places and the displacement (Warp By Vector in ParaView).
    if grid.GetNumberOfPoints() == 0:  # a step without contact points
        return [], [], np.zeros((0, 3))
    points = vtk_to_numpy(grid.GetPoints().GetData()) + vtk_to_numpy(grid.GetPointData().GetArray("displacement"))
    beam_array = grid.GetCellData().GetArray("beam")
    force_array = grid.GetPointData().GetArray("contact force")
    forces = vtk_to_numpy(force_array) if force_array is not None else np.zeros_like(points)
    faces, contacts = [], []
    for i in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(i)
        if cell.GetCellType() == vtk.VTK_VERTEX:
            pid = cell.GetPointId(0)
            contacts.append((points[pid], forces[pid]))
            continue
        beam = int(beam_array.GetValue(i)) if beam_array is not None else 0
        for f in range(cell.GetNumberOfFaces()):
            face = cell.GetFace(f)
            ids = [face.GetPointId(k) for k in range(face.GetNumberOfPoints())]
            faces.append((points[ids], beam))
    return faces, contacts, points


def layout(stages):
    """Rows and columns of the panels for this many stages: one row up to three (1 -> 1 x 1, 3 -> 1 x 3),
    then about square with the extra column (4 -> 2 x 2, 5 and 6 -> 2 x 3, 7 to 9 -> 3 x 3)."""
    if stages <= 3:
        return 1, stages
    cols = math.ceil(math.sqrt(stages))
    return math.ceil(stages / cols), cols


def deck_title(results):
    """The title of the run's deck: its top-level "Title" parameter if it has one; for a case of a study
    (STUDY_DIR/cases/NNN) the study's title and the case; else the deck's file name without its folder
    (from the command line the run recorded), else the results folder's name."""
    study = results.resolve().parent.parent / "study.json"
    if results.resolve().parent.name == "cases" and study.is_file():
        try:
            return f"{json.loads(study.read_text())['title']}, case {results.resolve().name}"
        except (OSError, ValueError, KeyError):
            pass
    effective = results / "effective_parameters.xml"
    try:
        root = ET.parse(effective).getroot()
        title = root.find("Parameter[@name='Title']")
        if title is not None and title.get("value"):
            return title.get("value")
    except (OSError, ET.ParseError):
        pass
    try:
        for line in (results / "status.txt").read_text().splitlines():
            if line.startswith("command:"):
                words = shlex.split(line[len("command:"):])
                decks = [w for w in words[words.index("run") + 1:] if w.endswith(".xml")] if "run" in words else []
                if decks:
                    return os.path.basename(decks[0])
    except (OSError, ValueError):
        pass
    return results.resolve().name


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("out")
    ap.add_argument("--stages", default="0.25,0.5,0.75,1")
    ap.add_argument("--view", default="22,-60")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    results = Path(a.results)
    out = Path(a.out)
    if out.is_symlink() or (out.exists() and not out.is_file()):
        sys.exit(f"beamcontact: render: {a.out} is not a regular file (a link, a folder, a device or a pipe); "
                 "give the path of a PNG file")
    folder = Path(a.out).parent
    if not folder.is_dir():
        sys.exit(f"beamcontact: render: cannot write {a.out}: {folder} is not a directory")
    pvd = results / "results.pvd"
    if not pvd.exists():
        sys.exit(f"beamcontact: render: {pvd} does not exist (is {results} a results directory written with VTK output?)")
    steps = [(float(d.get("timestep")), d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet")]
    try:
        stages = [float(s) for s in a.stages.split(",")]
        elev, azim = (float(v) for v in a.view.split(","))
    except ValueError:
        sys.exit(f"beamcontact: render: --stages takes numbers like 0.25,0.5,1 and --view two numbers ELEV,AZIM; got "
                 f"{a.stages!r} and {a.view!r}")
    if not steps:
        sys.exit(f"beamcontact: render: {pvd} lists no step")
    chosen = [min(steps, key=lambda s: abs(s[0] - t)) for t in stages]
    # The contact points of the same step (the same load factor), in their own series.
    contact_pvd = results / "contact.pvd"
    contact = {}
    if contact_pvd.exists():
        contact = {d.get("timestep"): d.get("file") for d in ET.parse(contact_pvd).getroot().iter("DataSet")}
    timestep = {f: d.get("timestep") for d in ET.parse(pvd).getroot().iter("DataSet") for f in [d.get("file")]}
    data = [read(results / f, results / contact[timestep[f]] if timestep[f] in contact else None) for _, f in chosen]
    allpts = np.vstack([d[2] for d in data])
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    span = float((hi - lo).max())
    fmax = max([np.linalg.norm(f) for d in data for _, f in d[1]] + [0.0])

    rows, cols = layout(len(chosen))
    # The title wrapped to the figure's width (about 11 characters an inch at 11 points), with room above
    # the panels for its lines.
    title = a.title or (f"{deck_title(results)}: stages of deformation (contact forces on beam B in red, the "
                        f"largest {fmax:.4g} in the model's force units)")
    title = textwrap.fill(title, int(11 * PANEL[0] * cols))
    head = 0.55 + 0.22 * (title.count("\n") + 1)
    fig = plt.figure(figsize=(PANEL[0] * cols, PANEL[1] * rows + head))
    for k, ((T, _), (faces, contacts, _)) in enumerate(zip(chosen, data)):
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
        polys = Poly3DCollection([f for f, _ in faces], facecolors=[COLOURS[b % len(COLOURS)] for _, b in faces],
                                 edgecolors="0.25", linewidths=0.2, alpha=0.9)
        ax.add_collection3d(polys)
        for p, f in contacts:
            n = np.linalg.norm(f)
            if n > 0 and fmax > 0:
                d = f / fmax * 0.25 * span
                ax.quiver(p[0], p[1], p[2], d[0], d[1], d[2], color="crimson", linewidth=1.5, arrow_length_ratio=0.25)
                ax.scatter([p[0]], [p[1]], [p[2]], color="crimson", s=8)
        mid = 0.5 * (lo + hi)
        for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid):
            setter(c - 0.5 * span, c + 0.5 * span)
        ax.set_box_aspect((1, 1, 1), zoom=0.85)
        ax.view_init(elev=elev, azim=azim)
        # The decks state no units (consistent length and force units are the user's): said so.
        ax.set_xlabel("X (model units)")
        ax.set_ylabel("Y (model units)")
        ax.set_zlabel("Z (model units)")
        ax.set_title(f"T = {T:g}, {len(contacts)} contact point{'s' if len(contacts) != 1 else ''}")
    fig.suptitle(title, fontsize=11)
    # Each panel fills its share of the figure (rows 0.4 inches apart for the titles of the next row);
    # the 3D box is drawn at 85 % so that its axis labels fit.
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=1.0 - head / fig.get_figheight(), wspace=0.0,
                        hspace=0.4 / PANEL[1])
    # An output path that cannot be written (its folder missing or read-only, a file in place of the
    # folder) is the caller's to fix: a usage error naming the path.
    try:
        fig.savefig(a.out, dpi=figure_style.DPI)
    except OSError as e:
        sys.exit(f"beamcontact: render: cannot write {a.out}: {e.strerror or e}")
    print(f"render: {a.out}")


if __name__ == "__main__":
    # Usage errors exit 1 (argparse: 2) with one line, a missing module exit 4 (need); anything else is
    # one line and exit 3.
    try:
        main()
    except SystemExit:
        raise
    except Exception as e:  # noqa: BLE001 - reported as one line, not a traceback
        print(f"beamcontact: render: {type(e).__name__}: {e}", file=sys.stderr)
        sys.exit(3)
