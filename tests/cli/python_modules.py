#!/usr/bin/python3
"""A missing Python module is one line naming its Debian package, with the documented exit code 4,
and a study's report names who wrote it:
- `render` of Example 1's results with numpy, matplotlib or vtk made unimportable (a sitecustomize.py
  on PYTHONPATH whose import hook raises ModuleNotFoundError for it, as Python does for a module that
  is not installed): exit 4, stderr exactly one line naming the module and python3-numpy,
  python3-matplotlib or python3-vtk9, and no picture;
- a study of two cases (tests/cli/decks/tiny_timing_study.xml) with its report: exit 0; cases.csv
  names each case's version and commit, study.json and report.md the study's (those of --version);
- the same study again (its complete cases kept) with matplotlib missing: exit 4, stderr exactly one
  line naming python3-matplotlib and --no-report, stdout saying every case is complete and the report
  was not written, cases.csv with both cases complete and no report.md; with --no-report: exit 0;
  the line comes before the first case runs (the study checks the report's modules first);
- vtk for render, matplotlib for the study, broken (their import raises RuntimeError): exit 4, one line
  saying the module cannot be loaded and to reinstall its package;
- paraview_views.py without ParaView's Python (paraview unimportable): exit 4, one line naming the
  Debian package paraview and pvpython;
- the report script failing after its imports (matplotlib's Figure.savefig raises): exit 4 and a line
  saying the report was not written and every case is complete, no report.md.

    python_modules.py BEAMCONTACT SOURCE_DIR WORKDIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys

exe, src, work = (os.path.abspath(a) for a in sys.argv[1:4])
shutil.rmtree(work, ignore_errors=True)
hooks = os.path.join(work, "hooks")
os.makedirs(hooks)
with open(os.path.join(hooks, "sitecustomize.py"), "w") as f:
    f.write('''import importlib.util
import os
import sys

BLOCKED = set(filter(None, os.environ.get("BC_TEST_MISSING_MODULES", "").split(",")))
BROKEN = set(filter(None, os.environ.get("BC_TEST_BROKEN_MODULES", "").split(",")))
FAILING_SAVEFIG = os.environ.get("BC_TEST_FAILING_SAVEFIG") == "1"


class Hook:
    def find_spec(self, name, path=None, target=None):
        top = name.split(".")[0]
        if top in BLOCKED:
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        if top in BROKEN:
            raise RuntimeError(f"{name} is broken (test)")
        if name == "matplotlib.figure" and FAILING_SAVEFIG:
            # The real module, whose Figure.savefig then fails: a report script that fails after its imports.
            sys.meta_path.remove(self)
            try:
                spec = importlib.util.find_spec(name)
            finally:
                sys.meta_path.insert(0, self)
            run = spec.loader.exec_module

            def exec_module(module):
                run(module)

                def savefig(*args, **kwargs):
                    raise OSError("savefig fails (test)")
                module.Figure.savefig = savefig
            spec.loader.exec_module = exec_module
            return spec
        return None


sys.meta_path.insert(0, Hook())
''')


def fail(message):
    sys.exit(f"FAIL: {message}")


def run(args, missing="", broken="", failing_savefig=False):
    env = dict(os.environ, PYTHONPATH=hooks, BC_TEST_MISSING_MODULES=missing, BC_TEST_BROKEN_MODULES=broken,
               BC_TEST_FAILING_SAVEFIG="1" if failing_savefig else "0")
    return subprocess.run([exe] + args, capture_output=True, text=True, env=env)


def one_line(r):
    lines = [l for l in r.stderr.splitlines() if l.strip()]
    if len(lines) != 1:
        fail(f"expected one line on stderr, got {len(lines)}: {r.stderr!r}")
    return lines[0]


results = os.path.join(work, "example1")
r = run(["run", os.path.join(src, "input", "example1.xml"), "--output", results, "--quiet"])
if r.returncode != 0:
    fail(f"Example 1: exit {r.returncode}: {r.stderr}")

for module, package in (("numpy", "python3-numpy"), ("matplotlib", "python3-matplotlib"), ("vtk", "python3-vtk9")):
    png = os.path.join(work, f"without_{module}.png")
    r = run(["render", results, png], missing=module)
    line = one_line(r)
    if r.returncode != 4 or f"module {module} is not installed" not in line or package not in line:
        fail(f"render without {module}: exit {r.returncode}, {line!r}")
    if os.path.exists(png):
        fail(f"render without {module} wrote {png}")
    print(f"ok: render without {module}: exit 4, {line!r}")
r = run(["render", results, os.path.join(work, "broken_vtk.png")], broken="vtk")
line = one_line(r)
if r.returncode != 4 or "module vtk cannot be loaded (RuntimeError: " not in line or \
        "apt install --reinstall python3-vtk9" not in line:
    fail(f"render with vtk broken: exit {r.returncode}, {line!r}")
print(f"ok: render with vtk broken: exit 4, {line!r}")
# ParaView's views script run without ParaView's Python (here made unimportable): the package and pvpython.
views = os.path.join(os.path.dirname(exe), "..", "share", "beamcontact", "paraview_views.py")
env = dict(os.environ, PYTHONPATH=hooks, BC_TEST_MISSING_MODULES="paraview")
r = subprocess.run(["/usr/bin/python3", views, results, work], capture_output=True, text=True, env=env)
line = one_line(r)
if r.returncode != 4 or "module paraview is not installed" not in line or "apt install paraview" not in line or \
        "pvpython" not in line:
    fail(f"paraview_views.py without paraview: exit {r.returncode}, {line!r}")
print(f"ok: paraview_views.py without paraview: exit 4, {line!r}")

commit = dict(l.split(": ", 1) for l in run(["--version"]).stdout.splitlines()[1:])["commit"]
version = run(["--version"]).stdout.splitlines()[0].split()[1]
study_deck = os.path.join(src, "tests", "cli", "decks", "tiny_timing_study.xml")
study = os.path.join(work, "study")
r = run(["study", study_deck, "--output", study, "--parallel", "2"])
if r.returncode != 0:
    fail(f"study: exit {r.returncode}: {r.stderr}")
rows = list(csv.DictReader(open(os.path.join(study, "cases.csv"))))
if [(x["status"], x["version"], x["commit"]) for x in rows] != [("complete", version, commit)] * 2:
    fail(f"cases.csv: {[(x['status'], x['version'], x['commit']) for x in rows]}, --version: {version} {commit}")
meta = json.load(open(os.path.join(study, "study.json")))["provenance"]
if (meta["version"], meta["commit"], meta["ranks"]) != (version, commit, "1") or "study" not in meta["command"]:
    fail(f"study.json provenance: {meta}")
report = open(os.path.join(study, "report.md")).read()
if "## Provenance" not in report or f"BeamContact {version}, commit {commit} (" not in report:
    fail("report.md does not name the version and commit")
print(f"ok: study: cases.csv, study.json and report.md name version {version}, commit {commit}")

r = run(["study", study_deck, "--output", study], missing="matplotlib")
line = one_line(r)
if r.returncode != 4 or "python3-matplotlib" not in line or "--no-report" not in line:
    fail(f"study without matplotlib: exit {r.returncode}, {line!r}")
if "every case complete, the report not written" not in r.stdout:
    fail(f"study without matplotlib: stdout {r.stdout!r}")
rows = list(csv.DictReader(open(os.path.join(study, "cases.csv"))))
if [x["status"] for x in rows] != ["complete", "complete"] or os.path.exists(os.path.join(study, "report.md")):
    fail("study without matplotlib: cases.csv not complete, or a report.md left")
# The line comes before the study starts its cases (stdout and stderr in one pipe, in their order).
env = dict(os.environ, PYTHONPATH=hooks, BC_TEST_MISSING_MODULES="matplotlib")
both = subprocess.run([exe, "study", study_deck, "--output", study], stdout=subprocess.PIPE,
                      stderr=subprocess.STDOUT, text=True, env=env).stdout.splitlines()
first = [i for i, l in enumerate(both) if "python3-matplotlib" in l]
start = [i for i, l in enumerate(both) if l.startswith("study tiny_timing_study: 2 cases from")]
if not first or not start or first[0] > start[0]:
    fail(f"the missing module's line does not come before the study starts: {both}")
print(f"ok: study without matplotlib: exit 4, {line!r}, before the cases start")

r = run(["study", study_deck, "--output", study, "--no-report"], missing="matplotlib")
if r.returncode != 0 or r.stderr.strip():
    fail(f"study --no-report without matplotlib: exit {r.returncode}, {r.stderr!r}")
print("ok: study --no-report without matplotlib: exit 0")

r = run(["study", study_deck, "--output", study], broken="matplotlib")
line = one_line(r)
if r.returncode != 4 or "module matplotlib cannot be loaded" not in line or "--no-report" not in line:
    fail(f"study with matplotlib broken: exit {r.returncode}, {line!r}")
print(f"ok: study with matplotlib broken: exit 4, {line!r}")

r = run(["study", study_deck, "--output", study], failing_savefig=True)
if r.returncode != 4 or "study report not written" not in r.stderr or "every case is complete" not in r.stderr:
    fail(f"study with a failing report: exit {r.returncode}, {r.stderr[-300:]!r}")
if os.path.exists(os.path.join(study, "report.md")):
    fail("study with a failing report: a report.md left")
print("ok: study whose report script fails (savefig): exit 4, the report not written, every case complete")
