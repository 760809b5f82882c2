#!/usr/bin/python3
"""Runs that fill their disk: Example 1 writes into small tmpfs file systems (10 sizes, so the disk fills
at different files and steps). Each run must end with exit code 2 (or 0 when it fitted), and then:
status.txt's first line says "failed: cannot write ...: No space left on device" (never "running"),
every CSV ends with a whole row, and steps.csv, newton.csv, tracked_points.csv and reactions.csv end at
the same step (a step is committed to all of them or to none).

    disk_full_tmpfs.py BEAMCONTACT DECK WORKDIR

Needs to mount tmpfs (root); exits 77 (skipped) where that is not allowed.
"""
import csv
import os
import subprocess
import sys

exe, deck, work = (os.path.abspath(a) for a in sys.argv[1:4])
os.makedirs(work, exist_ok=True)
mnt = os.path.join(work, "disk")
os.makedirs(mnt, exist_ok=True)
subprocess.run(["umount", mnt], capture_output=True)
probe = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", mnt], capture_output=True, text=True)
if probe.returncode != 0:
    print("skipped: cannot mount tmpfs here:", probe.stderr.strip())
    sys.exit(77)
subprocess.run(["umount", mnt])


def last_step(path):
    rows = list(csv.reader(open(path)))
    return int(rows[-1][0]) if len(rows) > 1 else 0


failed = 0
filled = 0
for kb in (96, 160, 240, 320, 480, 640, 900, 1200, 1600, 2400):
    subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={kb}k", "tmpfs", mnt], check=True)
    try:
        out = os.path.join(mnt, "results")
        r = subprocess.run([exe, "run", deck, "--output", out, "--quiet"], capture_output=True, text=True, timeout=120)
        problems = []
        status = open(os.path.join(out, "status.txt")).read().splitlines() if os.path.exists(os.path.join(out, "status.txt")) else []
        first = status[0] if status else "(no status.txt)"
        if r.returncode == 0:
            if not first.startswith("complete: "):
                problems.append(f"exit 0 with status {first!r}")
        elif r.returncode == 2:
            filled += 1
            if not (first.startswith("failed: cannot write ") and "No space left on device" in first):
                problems.append(f"status {first!r}")
        elif r.returncode == 1 and "cannot" in r.stderr:
            # The disk was too small for the results directory itself: refused before the run.
            filled += 1
            first = r.stderr.strip()
        else:
            problems.append(f"exit {r.returncode}: {r.stderr.strip()[-300:]}")
        csvs = [f for f in ("steps.csv", "newton.csv", "tracked_points.csv", "reactions.csv", "contact_points.csv")
                if os.path.exists(os.path.join(out, f))]
        for f in csvs:
            data = open(os.path.join(out, f), "rb").read()
            if data and not data.endswith(b"\n"):
                problems.append(f"{f} ends mid-row")
        ends = {f: last_step(os.path.join(out, f)) for f in csvs if f != "contact_points.csv"}
        if len(set(ends.values())) > 1:
            problems.append(f"the CSVs end at different steps: {ends}")
        if "contact_points.csv" in csvs and ends and last_step(os.path.join(out, "contact_points.csv")) > max(ends.values()):
            problems.append("contact_points.csv holds a step the other CSVs lack")
        print(f"{'FAIL' if problems else 'ok  '} {kb:5d} kB: exit {r.returncode}, steps {sorted(set(ends.values()))}, "
              f"{first[:110]}" + ("; " + "; ".join(problems) if problems else ""))
        failed += bool(problems)
    finally:
        subprocess.run(["umount", mnt])
assert filled >= 5, f"only {filled} of the runs filled their disk; make the file systems smaller"
print(f"{10 - failed} of 10 runs on a filling disk end with a true status and CSVs that agree")
sys.exit(1 if failed else 0)
