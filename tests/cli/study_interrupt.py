#!/usr/bin/python3
"""Stops a study with SIGTERM and runs it again (tests/cli/decks/slow_study.xml, two cases at a time):
- the study exits with 143 (128 + SIGTERM) soon after the signal, and no case process (worker, or
  with --process-per-case the cases' own processes) outlives it;
- cases.csv lists all four cases: those that were running "interrupted" (with their cause), those not
  started "not run"; no case directory says "running";
- run again, the study keeps the complete cases (says so) and runs the others: exit 0, four complete,
  and each F_N equals the one of an uninterrupted run of the same deck alone;
- Ctrl-C at a terminal (SIGINT to the study's whole process group): exit 130, and cases.csv agrees with
  every case's own status.txt (a case recorded complete says so itself; an interrupted one names the
  signal).
Usage: study_interrupt.py BEAMCONTACT DECK WORKDIR [--process-per-case]"""
import os
import csv
import signal
import subprocess
import sys
import time
from pathlib import Path

exe, deck, out = sys.argv[1], sys.argv[2], Path(sys.argv[3])
how = sys.argv[4:]  # how the cases run: nothing (the pool of workers) or --process-per-case
subprocess.run(["rm", "-rf", str(out)])
p = subprocess.Popen([exe, "study", deck, "--output", str(out), "--parallel", "2", "--no-report", *how],
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
# The signal goes once case 3 is running (cases 1 and 2 may be complete or running then).
started = out / "cases" / "003" / "status.txt"
deadline = time.time() + 60
while time.time() < deadline and not (started.exists() and started.read_text().startswith("running")):
    time.sleep(0.02)
p.send_signal(signal.SIGTERM)
t0 = time.time()
text, _ = p.communicate(timeout=60)
print(text)
assert p.returncode == 143, f"exit {p.returncode}, expected 143"
assert time.time() - t0 < 20, "the study took too long to stop"
left = subprocess.run(["pgrep", "-f", str(out / "cases")], capture_output=True, text=True).stdout.strip()
assert not left, f"case processes outlived the study: {left}"
rows = list(csv.DictReader(open(out / "cases.csv")))
assert len(rows) == 4, rows
statuses = [r["status"] for r in rows]
print("after SIGTERM:", statuses)
assert "interrupted" in statuses, statuses
assert all(s in ("complete", "interrupted", "not run") for s in statuses), statuses
for r in rows:
    if r["status"] == "interrupted":
        assert "SIGTERM" in r["cause"], r["cause"]
    status = (out / "cases" / f"{int(r['case']):03d}" / "status.txt")
    if status.exists():
        assert not status.read_text().startswith("running"), f"case {r['case']} still says running"

again = subprocess.run([exe, "study", deck, "--output", str(out), "--parallel", "2", "--no-report", *how],
                       capture_output=True, text=True)
print(again.stdout, again.stderr)
assert again.returncode == 0, f"rerun exit {again.returncode}"
complete_before = statuses.count("complete")
if complete_before:
    assert f"({complete_before} complete from an earlier run, kept)" in again.stdout, "kept cases not reported"
rows = list(csv.DictReader(open(out / "cases.csv")))
assert [r["status"] for r in rows] == ["complete"] * 4, rows
# Case 4 run alone, uninterrupted, gives the same normal force.
alone = out / "alone"
r = subprocess.run([exe, "run", str(out / "cases" / "004" / "deck.xml"), "--output", str(alone), "--quiet"])
assert r.returncode == 0
total = sum(float(l.split(",")[11]) for l in open(alone / "contact_points.csv").read().splitlines()[1:]
            if l.split(",")[1] == "1" and l.split(",")[16] == "1")
assert abs(total - float(rows[3]["F_N"])) <= 1e-9 * abs(total), (total, rows[3]["F_N"])
print(f"ok: stopped with {statuses}, resumed to 4 complete; case 4 F_N {rows[3]['F_N']} equals a run alone")

# Ctrl-C at a terminal: SIGINT to the foreground process group the study leads.
subprocess.run(["rm", "-rf", str(out)])
p = subprocess.Popen([exe, "study", deck, "--output", str(out), "--parallel", "2", "--no-report", *how],
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
deadline = time.time() + 60
while time.time() < deadline and not (started.exists() and started.read_text().startswith("running")):
    time.sleep(0.02)
os.killpg(p.pid, signal.SIGINT)
text, _ = p.communicate(timeout=60)
assert p.returncode == 130, f"exit {p.returncode} after SIGINT to the group, expected 130"
rows = list(csv.DictReader(open(out / "cases.csv")))
for r in rows:
    status = out / "cases" / f"{int(r['case']):03d}" / "status.txt"
    first = status.read_text().splitlines()[0] if status.exists() else ""
    if r["status"] == "complete":
        assert first.startswith("complete: "), (r, first)
    elif r["status"] == "interrupted" and first:
        assert first.startswith("interrupted: ") and r["cause"] == first[len("interrupted: "):], (r, first)
    elif r["status"] == "interrupted":  # stopped before its run wrote a status
        assert r["cause"] in ("stopped by SIGTERM", "stopped by SIGINT"), r
    else:
        assert r["status"] == "not run" and not first, (r, first)
print("ok: after SIGINT to the process group:", [r["status"] for r in rows], "each as its status.txt says")
