#!/usr/bin/python3
"""The command line's conventions (issue 34 item 5), each checked on the program:

    conventions.py BEAMCONTACT SOURCE_DIR WORKDIR

- every subcommand (run, check, study, render, version, generate and each generator,
  --print-valid-parameters) answers --help and -h with exit 0, its usage line first, every option
  this script expects (listed below, not read from the program) with "(default: ...)", nothing on
  stderr and nothing from Kokkos;
- --opt=value and --opt value alike; -o for --output and -q for --quiet; options before the deck;
- a usage error is one line on stderr naming the problem, with "(see beamcontact CMD --help)", exit 1,
  nothing on stdout;
- --quiet prints nothing on a complete run; without --timers the timer table is not on stdout (nor
  Teuchos' three-line note on 1 rank) but in timers.txt, with --timers on stdout too;
- the step lines show T, Newton iterations, the step's time and the time left; a complete run ends with
  its tracked points at T = 1: example1's A and B, the values of tracked_points.csv's last row, each
  followed by the paper's values (docs/paper-comparison.md) with the difference from the run's;
- study --quiet prints nothing when every case completes.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

exe, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
deck = os.path.join(src, "input", "example1.xml")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, timeout=120)


def read(path):
    return open(path).read() if os.path.exists(path) else ""


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


PLUGIN = ["--plugin"]
COMMON = ["--radius", "--youngs-modulus", "--friction", "--penalty", "--increments", "--output", "-o", "--overwrite"]
EXPECTED = {
    ("run",): ["--output", "-o", "--overwrite", "--quiet", "-q", "--timers", "--restart"] + PLUGIN,
    ("check",): PLUGIN,
    ("study",): ["--output", "-o", "--overwrite", "--parallel", "--timing", "--no-report", "--process-per-case",
                 "--quiet", "-q"] + PLUGIN,
    ("render",): ["--stages", "--view", "--title"],
    ("version",): [],
    ("--print-valid-parameters",): ["--format"] + PLUGIN,
    ("generate",): ["grid", "weave", "network", "strand"],
    ("generate", "grid"): COMMON + ["--spacing", "--n", "--m", "--gap", "--press", "--load", "--elements"],
    ("generate", "weave"): COMMON + ["--spacing", "--n", "--m", "--gap", "--pull", "--elements"],
    ("generate", "network"): COMMON + ["--fibres", "--box", "--height", "--length", "--tilt", "--gap", "--min-angle",
                                       "--compress", "--seed", "--elements"],
    ("generate", "strand"): COMMON + ["--wires", "--core", "--core-radius", "--lay-length", "--turns", "--gap",
                                      "--stretch", "--regularization", "--elements"],
}
for command, options in EXPECTED.items():
    for flag in ("--help", "-h"):
        r = run(*command, flag)
        name = " ".join(command)
        check(r.returncode == 0, f"{name} {flag}: exit {r.returncode}")
        check(r.stdout.startswith("usage: beamcontact " + name), f"{name} {flag}: first line {r.stdout[:60]!r}")
        check(r.stderr == "", f"{name} {flag}: stderr {r.stderr[:200]!r}")
        check("kokkos" not in r.stdout.lower(), f"{name} {flag}: Kokkos' help printed")
        for option in options:
            # An option's row: the option as a word, and (generators, subcommands) its default on its row.
            rows = [l for l in r.stdout.splitlines() if re.search(r"(^|[ ,])" + re.escape(option) + r"([ ,=]|$)", l)]
            check(rows, f"{name} {flag}: {option} not listed")
        if command != ("generate",):
            listed = len(re.findall(r"^ +(-\w, )?--[\w-]+", r.stdout, re.M)) - 1  # less --help's own row
            text = " ".join(r.stdout.split())
            check(text.count("(default: ") == listed, f"{name} {flag}: {listed} options, "
                  f"{text.count('(default: ')} defaults")
            check(listed == len([o for o in options if o.startswith("--")]), f"{name}: {listed} options listed")

# A usage error: one line, the problem and the hint, exit 1, stdout empty.
for args, problem, hint in [
    (["run", deck, "--verbose"], 'unknown option "--verbose"', "run"),
    (["run", deck, "--output"], 'missing DIR after "--output"', "run"),
    (["run", "--quiet=yes", deck], '--quiet takes no value', "run"),
    (["run"], "missing DECK.xml", "run"),
    (["run", deck, deck], f'unexpected argument "{deck}"', "run"),
    (["check", deck, "--timers"], 'unknown option "--timers"', "check"),
    (["study", deck, "--parallel=0"], '--parallel takes a whole number from 1 to 1024, got "0"', "study"),
    (["render", work], "missing OUT.png", "render"),
    (["generate", "grid", "--n=two"], '--n takes a number, got "two"', "generate grid"),
    (["generate", "grid", "--q", "1"], 'unknown option "--q"', "generate grid"),
    (["generate", "gird"], 'unknown kind "gird"', "generate"),
]:
    r = run(*args)
    lines = r.stderr.splitlines()
    check(r.returncode == 1, f"{args}: exit {r.returncode}")
    check(r.stdout == "", f"{args}: stdout {r.stdout[:200]!r}")
    check(len(lines) == 1 and problem in lines[0] and lines[0].endswith(f"(see beamcontact {hint} --help)"),
          f"{args}: stderr {r.stderr!r}")

# -q, -o and options before the deck; --quiet prints nothing on success.
out = os.path.join(work, "short")
r = run("run", "-q", "-o", out, deck)
check(r.returncode == 0 and r.stdout == "" and r.stderr == "", f"run -q -o DIR DECK: {r.returncode} {r.stdout!r} {r.stderr!r}")
check(read(os.path.join(out, "status.txt")).startswith("complete: 50 steps"), "-o: no complete status")
# --opt=value, --quiet.
out = os.path.join(work, "equals")
r = run("run", f"--output={out}", "--quiet", deck)
check(r.returncode == 0 and r.stdout == "" and r.stderr == "", f"run --output=DIR: {r.returncode} {r.stdout!r}")
check(os.path.isfile(os.path.join(out, "status.txt")), "--output=DIR: no status.txt in DIR")

# Without --timers: step lines, tracked points and the closing line; the table only in timers.txt.
out = os.path.join(work, "plain")
r = run("run", deck, "--output", out)
check(r.returncode == 0, f"run: exit {r.returncode}")
lines = r.stdout.splitlines()
timers = read(os.path.join(out, "timers.txt"))
check("Linear Solve" in timers and "Assembly" in timers, "timers.txt lacks the timer table")
check("Linear Solve" not in r.stdout and "***" not in r.stdout and "Remainder" not in r.stdout,
      "the timer table or its banner is on stdout without --timers")
steps = [l for l in lines if l.startswith("step ")]
check(len(steps) == 50, f"{len(steps)} step lines")
pace = re.compile(r"T = ([0-9.]+)  Newton +(\d+) .*  [0-9.]+ (ms|s)/step(, .* left)?$")
check(all(pace.search(l) for l in steps), f"a step line without its time: {steps[0]!r}")
check(all(" left" in l for l in steps[:-1]) and " left" not in steps[-1], "time left missing before T = 1")
check(steps[-1].startswith("step   50  T = 1.000000"), f"last step line {steps[-1]!r}")
# The tracked points at T = 1, as tracked_points.csv's last row has them (6 significant digits).
last = list(csv.DictReader(read(os.path.join(out, "tracked_points.csv")).splitlines()))[-1]
check(float(last["T"]) == 1.0, "tracked_points.csv does not end at T = 1")
for point in ("A", "B"):
    row = [l for l in lines if l.startswith(f"at T = 1: {point}: u = (")]
    check(len(row) == 1, f"no line for tracked point {point}")
    if row:
        shown = [float(x) for x in row[0].split("(")[1].rstrip(")").split(",")]
        for value, c in zip(shown, "xyz"):
            want = float(last[f"{point}_u{c}"])
            check(abs(value - want) <= 1e-5 * max(1.0, abs(want)), f"{point} u{c}: shown {value}, csv {want}")
check(lines and lines[-1].startswith("complete: 50 steps"), f"last line {lines[-1]!r}")
check(not any(l.startswith("at T = 1") for l in lines[:-5]), "tracked points before the end")
# The paper's values beside A's and B's (the deck's Reference ux, uz): those of docs/paper-comparison.md's
# "paper, Lagrange" row (magnitudes; A ux, A uz, B ux, B uz) with the signs of our axes, and the
# difference (run - paper) / paper of the values shown.
paper_row = re.search(r"^\| paper, Lagrange \|[^|]*\|[^|]*\| ([0-9.]+) \| ([0-9.]+) \| ([0-9.]+) \| ([0-9.]+) \|",
                      read(os.path.join(src, "docs", "paper-comparison.md")), re.M)
check(paper_row is not None, "docs/paper-comparison.md has no 'paper, Lagrange' row")
published = [float(x) for x in paper_row.groups()] if paper_row else [0, 0, 0, 0]
for point, table, (ux, uz) in (("A", 1, published[0:2]), ("B", 2, published[2:4])):
    row = [l for l in lines if l.startswith(f"at T = 1: {point}: u = (")]
    shown = [float(x) for x in row[0].split("(")[1].rstrip(")").split(",")] if row else [0, 0, 0]
    line = [l for l in lines if l.startswith(f"at T = 1: {point}: paper (Table {table}, Lagrange): ")]
    check(len(line) == 1, f"no paper line for {point}: {lines[-6:]}")
    if not line:
        continue
    values = re.findall(r"(u[xyz]) (-?[0-9.]+) \(diff ([+-][0-9.]+) %\)", line[0])
    check([v[0] for v in values] == ["ux", "uz"], f"{point}: paper line {line[0]!r}")
    for (component, value, diff), magnitude in zip(values, (ux, uz)):
        k = "xyz".index(component[1])
        check(abs(abs(float(value)) - magnitude) < 1e-12 and float(value) * shown[k] > 0,
              f"{point} {component}: paper {value}, docs {magnitude}, run {shown[k]}")
        want = 100 * (shown[k] - float(value)) / float(value)
        check(abs(float(diff) - want) <= 0.01, f"{point} {component}: diff {diff} %, expected {want:.3f} %")

# study --quiet: nothing printed when every case completes (report included), the table written.
out = os.path.join(work, "study_quiet")
r = run("study", "-q", "-o", out, os.path.join(src, "tests", "cli", "decks", "tiny_timing_study.xml"))
check(r.returncode == 0 and r.stdout == "" and r.stderr == "", f"study -q: {r.returncode} {r.stdout!r} {r.stderr!r}")
check(os.path.isfile(os.path.join(out, "cases.csv")) and os.path.isfile(os.path.join(out, "report.md")),
      "study -q: no cases.csv or report.md")

# With --timers the table is on stdout too, and no banner on 1 rank.
r = run("run", deck, "--output", os.path.join(work, "timers"), "--timers", "--quiet")
check(r.returncode == 0 and "Linear Solve" in r.stdout and "***" not in r.stdout, f"--timers: {r.stdout[:300]!r}")

# generate: --opt=value, -o.
grid = os.path.join(work, "grid.xml")
r = run("generate", "grid", "--n=2", "--m", "1", "-o", grid)
check(r.returncode == 0, f"generate grid --n=2 -o: exit {r.returncode} {r.stderr!r}")
text = read(grid)
check('name="x2"' in text and 'name="x3"' not in text and 'name="y1"' in text and 'name="y2"' not in text,
      "generate grid --n=2 --m 1: not 2 x 1 beams")
# An existing file (a deck the user edited) is replaced only with --overwrite.
with open(grid, "w") as f:
    f.write("my edited deck\n")
r = run("generate", "grid", "--n", "2", "--m", "1", "-o", grid)
check(r.returncode == 1 and "--overwrite" in r.stderr and read(grid) == "my edited deck\n",
      f"generate -o over an existing file: exit {r.returncode} {r.stderr!r}, file {read(grid)[:40]!r}")
r = run("generate", "grid", "--n", "2", "--m", "1", "-o", grid, "--overwrite")
check(r.returncode == 0 and 'name="x2"' in read(grid), f"generate -o --overwrite: exit {r.returncode} {r.stderr!r}")

# A negative number is a value, not an option: the top layer's ends move up by 0.5.
r = run("generate", "grid", "--n", "1", "--m", "1", "--press", "-0.5")
moves = [[float(x) for x in v.split(",")] for v in re.findall(r'name="Displacement"[^>]*value="\{([^}]*)\}"', r.stdout)]
check(r.returncode == 0 and [0.0, 0.0, 0.5] in moves, f"generate grid --press -0.5: {moves} {r.stderr!r}")

print(f"{len(failures)} failures" if failures else "ok: every convention holds")
sys.exit(1 if failures else 0)
