#!/usr/bin/python3
"""The figures are ready for a paper (docs/studies.md, "report.md"; issue 34 item 7):
- a small study (tests/cli/decks/figures_study.xml: Example 1 with Lagrange multipliers and Penalty
  at two eps_N) through `beamcontact study --no-report`, then its report drawn in this process by
  the scripts in SCRIPTS_DIR, each figure kept for inspection (matplotlib's objects);
- every report PDF: no Type 3 font (`/Subtype /Type3`; pdffonts too where poppler-utils is
  installed) and at least one TrueType font (Type 42: /CIDFontType2 or /TrueType);
- every PNG: its pixels are the figure's size in inches times 200 (+-1), and it says 200 dpi;
- the plot with the paper's four values without X (two share a label): one legend entry for the
  curve and one per value, each with its value, and four one-point markers of four different shapes,
  no line across the plot; the error plot's published value with X likewise one marker and entry;
- the load-displacement legend: "lagrange", "penalty eps_N=10000", "penalty eps_N=30000" (the group
  and the value it varies; not its strategy or predictor, which it sets once);
- every figure titled with the study's Title, every axis label with a unit: "[...]" or
  "(model units)";
- a study of 45 cases made up here (cases.csv, study.json and each case's CSV files, as the study
  driver writes them): every line of its load-displacement, Newton and Series plots has a
  (colour, marker, line style) of its own within its figure (the old cycle repeated at 11 cases in
  the plot and at 41 in the curves);
- render of the Lagrange case for 1, 2, 3, 4 and 6 stages: 1 x 1, 1 x 2, 1 x 3, 2 x 2, 2 x 3 panels,
  the PNG's width 5.2 inches per column at 200 dpi, the title the study's title and the case
  ("Figures test: Example 1, case 001"), axes in "(model units)"; `beamcontact render` with one stage
  writes a PNG one panel wide; and a run outside a study is titled with its deck's file name.

    figures.py BEAMCONTACT SCRIPTS_DIR DECK WORKDIR
"""
import csv
import importlib.util
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys

exe, scripts, deck, work = sys.argv[1], os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3]), sys.argv[4]
work = os.path.abspath(work)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print(f"FAIL: {message}")
    return ok


def load(name):
    spec = importlib.util.spec_from_file_location(name, os.path.join(scripts, name + ".py"))
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, scripts)
    spec.loader.exec_module(module)
    return module


study_dir = os.path.join(work, "study")
r = subprocess.run([exe, "study", deck, "--output", study_dir, "--parallel", "3", "--no-report"], capture_output=True,
                   text=True)
if r.returncode != 0:
    sys.exit(f"FAIL: study exit {r.returncode}: {r.stdout}{r.stderr}")

report = load("study_report")
from matplotlib.figure import Figure  # noqa: E402 - after the script set matplotlib up
from PIL import Image  # noqa: E402 - matplotlib's own dependency
saved = {}  # file stem -> figure
original_save = report.Study.save


def keep(self, fig, title):
    stem = original_save(self, fig, title)
    saved[stem] = fig
    return stem


report.Study.save = keep
report.main(study_dir)
title = json.load(open(os.path.join(study_dir, "study.json")))["title"]
print(f"figures: {sorted(saved)}")
check(set(saved) == {"A_uz_vs_eps_N", "A_uz_error_vs_eps_N", "Active_vs_eps_N", "curve_A_uz", "newton_per_step"},
      f"figures drawn: {sorted(saved)}")

pdffonts = shutil.which("pdffonts")


def check_files(directory, figures):
    for stem, fig in figures.items():
        pdf = open(os.path.join(directory, stem + ".pdf"), "rb").read()
        check(not re.search(rb"/Subtype\s*/Type3", pdf), f"{stem}.pdf has a Type 3 font")
        check(re.search(rb"/Subtype\s*/(CIDFontType2|TrueType)", pdf), f"{stem}.pdf has no TrueType font")
        if pdffonts:
            listing = subprocess.run([pdffonts, os.path.join(directory, stem + ".pdf")], capture_output=True,
                                     text=True).stdout
            check("Type 3" not in listing, f"pdffonts {stem}.pdf lists a Type 3 font:\n{listing}")
        with Image.open(os.path.join(directory, stem + ".png")) as png:
            want = [round(v * 200) for v in fig.get_size_inches()]
            check(all(abs(a - b) <= 1 for a, b in zip(png.size, want)),
                  f"{stem}.png is {png.size[0]} x {png.size[1]} pixels, {fig.get_size_inches()} inches at 200 dpi "
                  f"is {want[0]} x {want[1]}")
            dpi = png.info.get("dpi", (0, 0))
            check(all(abs(d - 200) < 1 for d in dpi), f"{stem}.png says {dpi} dpi")


def has_unit(label):
    return bool(re.search(r"\[[^\]]+\]|\(model units\)", label))


def legend_texts(fig):
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    return [t.get_text() for lg in legends for t in lg.get_texts()]


check_files(study_dir, saved)
for stem, fig in saved.items():
    check(fig._suptitle is not None and fig._suptitle.get_text() == title,
          f"{stem}: title {fig._suptitle.get_text() if fig._suptitle else None!r}, expected {title!r}")
    for ax in fig.axes:
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            check(has_unit(label), f"{stem}: axis label {label!r} has no unit")

# The paper's four values without X: one marker and one legend entry each, no lines.
fig = saved.get("A_uz_vs_eps_N")
if fig:
    texts = legend_texts(fig)
    want = ["A uz", "paper: penalty (range): A uz = -9.79", "paper: penalty (range): A uz = -9.82",
            "paper: Lagrange: A uz = -9.89", "paper: 3D solid: A uz = -9.87"]
    check(texts == want, f"A_uz_vs_eps_N legend {texts}, expected {want}")
    ax = fig.axes[0]
    published = [ln for ln in ax.get_lines() if ln.get_label().startswith("paper")]
    check(len(published) == 4 and all(len(ln.get_xdata()) == 1 and ln.get_linestyle() == "None"
                                       for ln in published),
          f"published values: {[(ln.get_label(), len(ln.get_xdata()), ln.get_linestyle()) for ln in published]}")
    check(len({ln.get_marker() for ln in published}) == 4, "the four published markers are not four shapes")
    lines = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-." and len(set(ln.get_ydata())) == 1]
    check(not lines, f"{len(lines)} dash-dot horizontal lines (the old published lines)")
fig = saved.get("A_uz_error_vs_eps_N")
if fig:
    texts = legend_texts(fig)
    check(len(texts) == 2 and texts[0].startswith("A uz (slope ") and texts[1] == "paper: penalty: A uz = -9.79",
          f"A_uz_error_vs_eps_N legend {texts}")
fig = saved.get("curve_A_uz")
if fig:
    texts = legend_texts(fig)
    check(texts == ["lagrange", "penalty eps_N=10000", "penalty eps_N=30000"], f"curve_A_uz legend {texts}")

# 45 cases made up: one group varying k = 1..45, each case's tracked point, steps and residuals.
big = os.path.join(work, "big")
n = 45
os.makedirs(big)
meta = {"title": "45 cases", "base_deck": "none.xml", "at_T": 1, "reference_group": "", "timing_runs": 0,
        "parallel": 1, "base": {}, "groups": [{"name": "sweep", "variables": [
            {"name": "k", "path": "A/B", "values": [str(k) for k in range(1, n + 1)]}]}],
        "units": {"u": "length"}, "columns": ["k"], "outputs": ["u"],
        "output_sources": {"u": {"tracked_point": "P", "component": "uz", "contact": ""}},
        "plots": [{"name": "u vs k", "x": "k", "y": "u", "series": "k", "relative_to": "", "log_x": False,
                   "error": False, "published_x": [], "published_y": [], "published_labels": []}]}
json.dump(meta, open(os.path.join(big, "study.json"), "w"))
fields = ["case", "group", "k", "status", "u", "newton_iterations", "max_newton_per_step", "passes", "steps",
          "last_T", "solve_seconds", "cause"]
with open(os.path.join(big, "cases.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fields)
    w.writeheader()
    for k in range(1, n + 1):
        w.writerow({"case": k, "group": "sweep", "k": k, "status": "complete", "u": -k / 10.0,
                    "newton_iterations": 10, "max_newton_per_step": 3, "passes": 5, "steps": 5, "last_T": 1,
                    "solve_seconds": 0.1, "cause": ""})
        case = os.path.join(big, "cases", f"{k:03d}")
        os.makedirs(case)
        with open(os.path.join(case, "tracked_points.csv"), "w") as t:
            t.write("step,T,P_uz\n" + "".join(f"{s},{s / 5},{-k * s / 50}\n" for s in range(6)))
        with open(os.path.join(case, "steps.csv"), "w") as t:
            t.write("step,T,newton_iterations\n" + "".join(f"{s},{s / 5},{2 + (k + s) % 3}\n" for s in range(1, 6)))
        with open(os.path.join(case, "newton.csv"), "w") as t:
            t.write("step,T,iteration,residual_norm\n" + "".join(f"5,1,{i},{10.0 ** (2 - 3 * i) * k}\n" for i in range(4)))
saved.clear()
report.main(big)
check_files(big, saved)
for stem in ("u_vs_k", "curve_u", "newton_per_step"):
    fig = saved.get(stem)
    if not check(fig is not None, f"45 cases: no figure {stem}"):
        continue
    for ax in fig.axes:
        styles = [(ln.get_color(), ln.get_marker(), ln.get_linestyle()) for ln in ax.get_lines()
                  if not ln.get_label().startswith("_")]
        check(len(styles) == n, f"45 cases, {stem}: {len(styles)} series")
        repeated = len(styles) - len(set(styles))
        check(repeated == 0, f"45 cases, {stem}: {repeated} series repeat another's colour, marker and line style")
    texts = legend_texts(fig)
    check(texts[:2] in (["k = 1", "k = 2"], ["sweep k=1", "sweep k=2"]), f"45 cases, {stem}: legend {texts[:2]}")
print(f"ok so far: 45 cases, {len(failures)} failures")

# render: the layout for the number of stages.
render = load("render_stages")
case = os.path.join(study_dir, "cases", "001")
rendered = []
original_savefig = Figure.savefig


def keep_figure(self, *args, **kwargs):
    rendered.append(self)
    return original_savefig(self, *args, **kwargs)


Figure.savefig = keep_figure
for stages, rows, cols in (("1", 1, 1), ("0.5,1", 1, 2), ("0.3,0.6,1", 1, 3), ("0.25,0.5,0.75,1", 2, 2),
                           ("0.2,0.4,0.6,0.8,0.9,1", 2, 3)):
    out = os.path.join(work, f"render_{len(stages.split(','))}.png")
    rendered.clear()
    sys.argv = ["render_stages.py", case, out, "--stages", stages]
    render.main()
    fig = rendered[0]
    grids = [ax.get_subplotspec().get_geometry()[:2] for ax in fig.axes]
    check(len(fig.axes) == len(stages.split(",")) and set(grids) == {(rows, cols)},
          f"render {stages}: {len(fig.axes)} panels on grids {set(grids)}, expected {rows} x {cols}")
    with Image.open(out) as png:
        check(abs(png.size[0] - round(5.2 * cols * 200)) <= 1 and
              abs(png.size[1] - round(fig.get_size_inches()[1] * 200)) <= 1 and
              all(abs(d - 200) < 1 for d in png.info.get("dpi", (0, 0))),
              f"render {stages}: {png.size} pixels, {png.info.get('dpi')} dpi, for {cols} columns at 200 dpi")
    check(fig._suptitle is not None and fig._suptitle.get_text().startswith(f"{title}, case 001: "),
          f"render {stages}: title {fig._suptitle.get_text() if fig._suptitle else None!r}")
    check(all("(model units)" in label for ax in fig.axes
              for label in (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel())), f"render {stages}: axis labels")
Figure.savefig = original_savefig
plain = os.path.join(work, "plain_run")
r = subprocess.run([exe, "run", os.path.join(os.path.dirname(deck), "..", "..", "..", "input", "example1.xml"),
                    "--output", plain, "--quiet"], capture_output=True, text=True)
check(r.returncode == 0 and render.deck_title(pathlib.Path(plain)) == "example1.xml",
      f"a run of example1.xml: exit {r.returncode}, render's title {render.deck_title(pathlib.Path(plain))!r}")
out = os.path.join(work, "render_cli.png")
r = subprocess.run([exe, "render", case, out, "--stages", "1"], capture_output=True, text=True)
if check(r.returncode == 0, f"beamcontact render --stages 1: exit {r.returncode}: {r.stderr}"):
    with Image.open(out) as png:
        check(abs(png.size[0] - 1040) <= 1, f"beamcontact render --stages 1: {png.size[0]} pixels wide, expected 1040")

if failures:
    sys.exit(f"FAIL: {len(failures)} checks failed")
print("ok: report PDFs with TrueType fonts only, PNGs at 200 dpi, published values as one marker and legend entry "
      "each, legends of the varied values, titles and units, 45 distinct series, render laid out per stage count")
