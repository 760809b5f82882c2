#!/usr/bin/python3
"""Kill a run at random moments, check what it left, restart it and compare with an uninterrupted run.

    kill_restart.py BEAMCONTACT DECK WORKDIR KILLS [MPIRUN...]

DECK must set Output/Checkpoint Every. The uninterrupted run goes to WORKDIR/full. Then KILLS times
(signals cycling SIGTERM, SIGINT, SIGKILL; moments drawn with a fixed seed between 30 % and 85 % of the
full run's wall time):
  - the killed run's status.txt is absent (killed while starting, before it wrote anything), or "interrupted: <signal> ..." for SIGTERM/SIGINT (exit 128 + N), or
    still "running (pid N)" with N no longer alive for SIGKILL, or "complete" if it finished first;
  - every CSV has whole lines only, each with the header's number of columns;
  - `run DECK --restart DIR` (with the MPIRUN prefix on odd kills, when given: another rank count)
    completes, and every row of every CSV equals the uninterrupted run's, numbers to 1e-9 of the
    file's largest magnitude (steps.csv's final_residual, a residual at its round-off floor, is not
    compared). Not as identical text on the same rank count: KLU2 refactors a matrix of the same graph
    with the pivot order of its first factorization since the graph last changed, a history a restart
    does not repeat (it factors afresh), so a checkpoint taken while contact acts restarts into solves
    that differ by round-off (measured: 2e-12 of a file's largest value, the final residual in its 4th
    digit; docs/faults.md). A checkpoint before contact restarts to identical text.
Prints one line per kill and a summary; exit 1 on the first failure.
"""
import os
import random
import signal
import subprocess
import sys
import time

exe, deck, work, kills = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
mpirun = sys.argv[5:]
CSVS = ["steps.csv", "tracked_points.csv", "reactions.csv", "contact_points.csv"]


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def rows(path):
    with open(path) as f:
        text = f.read()
    if text and not text.endswith("\n"):
        fail(f"{path} ends mid-line")
    lines = text.splitlines()
    width = lines[0].count(",")
    for i, line in enumerate(lines):
        if line.count(",") != width:
            fail(f"{path} line {i + 1} has {line.count(',') + 1} columns, the header {width + 1}")
    return lines


def number(s):
    try:
        return float(s)
    except ValueError:
        return None


def compare(full_dir, run_dir):
    for name in CSVS:
        a, b = rows(os.path.join(full_dir, name)), rows(os.path.join(run_dir, name))
        if len(a) != len(b):
            fail(f"{name}: {len(b)} lines after restart, {len(a)} uninterrupted")
        header = a[0].split(",")
        cols = [[number(x) for x in line.split(",")] for line in a[1:]]
        # One scale per file: the largest magnitude among its quantities (a component that stays near
        # zero, e.g. a transverse displacement, carries the round-off of the large ones).
        scale = max((abs(v) for r in cols for v in r[2:] if v is not None), default=0.0)
        for i, (la, lb) in enumerate(zip(a[1:], b[1:])):
            for c, (x, y) in enumerate(zip(la.split(","), lb.split(","))):
                if header[c] == "final_residual":
                    continue
                nx, ny = number(x), number(y)
                if nx is None or ny is None:
                    if x != y:
                        fail(f"{name} row {i + 1} column {c + 1}: {x} vs {y}")
                elif abs(nx - ny) > 1e-9 * max(scale, 1e-300):
                    fail(f"{name} row {i + 1} column {c + 1}: {x} vs {y} (file scale {scale:.3g})")


full = os.path.join(work, "full")
t0 = time.time()
r = subprocess.run([exe, "run", deck, "--output", full, "--quiet"], capture_output=True, text=True)
wall = time.time() - t0
if r.returncode != 0:
    fail(f"uninterrupted run exit {r.returncode}: {r.stderr}")
rng = random.Random(20261123)
signals = [signal.SIGTERM, signal.SIGINT, signal.SIGKILL]
counts = {}
for k in range(kills):
    sig = signals[k % 3]
    d = os.path.join(work, f"kill{k:02d}")
    subprocess.run(["rm", "-rf", d])
    p = subprocess.Popen([exe, "run", deck, "--output", d, "--quiet"], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    moment = rng.uniform(0.3, 0.85) * wall
    time.sleep(moment)
    p.send_signal(sig)
    code = p.wait()
    if not os.path.exists(os.path.join(d, "status.txt")):
        # Killed while starting (MPI start-up, reading the deck): nothing was written as a result.
        if os.path.exists(os.path.join(d, "summary.csv")):
            fail(f"kill {k}: a summary without a status")
        counts["killed while starting"] = counts.get("killed while starting", 0) + 1
        print(f"kill {k:2d}: {signal.Signals(sig).name:7s} at {moment:5.2f} s: killed while starting, no results")
        continue
    with open(os.path.join(d, "status.txt")) as f:
        status = f.readline().strip()  # the status (the provenance follows it)
    if status.startswith("complete"):
        verdict = "finished before the signal"
        if code not in (0, -sig, 128 + sig):  # a signal while exiting after the last write is harmless
            fail(f"kill {k}: complete but exit {code}")
    elif sig == signal.SIGKILL:
        if not status.startswith("running (pid "):
            fail(f"kill {k}: SIGKILL left status {status!r}")
        pid = int(status[len("running (pid "):].rstrip(")"))
        try:
            os.kill(pid, 0)
            fail(f"kill {k}: status names pid {pid}, which is alive")
        except ProcessLookupError:
            pass
        verdict = "running (pid dead)"
    else:
        name = signal.Signals(sig).name
        if not status.startswith(f"interrupted: {name} at T = "):
            fail(f"kill {k}: {name} left status {status!r}")
        if code != 128 + sig:
            fail(f"kill {k}: exit {code}, expected {128 + sig}")
        verdict = "interrupted"
    for name in CSVS:
        rows(os.path.join(d, name))
    checkpoint = os.path.exists(os.path.join(d, "checkpoint.txt"))
    steps_before = len(rows(os.path.join(d, "steps.csv"))) - 1
    if checkpoint:
        ranks = 2 if (mpirun and k % 2 == 1) else 1
        cmd = (mpirun if ranks == 2 else []) + [exe, "run", deck, "--restart", d, "--quiet"]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"kill {k}: restart exit {r.returncode}: {r.stderr.strip()[-300:]}")
        compare(full, d)
        verdict += f", restarted on {ranks} rank{'s' if ranks > 1 else ''}: every row matches"
    elif not status.startswith("complete"):
        verdict += ", killed before the first checkpoint"
    counts[verdict.split(",")[0]] = counts.get(verdict.split(",")[0], 0) + 1
    print(f"kill {k:2d}: {signal.Signals(sig).name:7s} at {moment:5.2f} s, {steps_before:3d} steps written: {verdict}")
print(f"ok: {kills} kills ({', '.join(f'{v} {k}' for k, v in sorted(counts.items()))}); uninterrupted run {wall:.2f} s")
