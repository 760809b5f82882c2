"""Runs the tiny timing study (tests/cli/decks/tiny_timing_study.xml) with `study --timing 3` and
checks that each case ran 3 times, one case at a time, without VTK output, and that cases.csv and
the report give the median solve time with its range:
- timing_runs = 3 and min <= median <= max for each case; the median is the middle of three runs,
  so it is one of the times the runs wrote (the last run's summary.csv holds one of them);
- every case deck has Output/Write VTK false and its results no VTK files;
- the report says it is a timing study and gives the range per group.
Timings themselves are not asserted: they are measurements, not results."""
import csv
import subprocess
import sys
from pathlib import Path

exe, deck, out = sys.argv[1], sys.argv[2], Path(sys.argv[3])
subprocess.run(["rm", "-rf", str(out)])
run = subprocess.run([exe, "study", deck, "--output", str(out), "--timing", "3"], capture_output=True, text=True)
print(run.stdout)
print(run.stderr)
assert run.returncode == 0, f"exit code {run.returncode}"
assert "1 at a time" in run.stdout and "each case 3 times, VTK off" in run.stdout, run.stdout
rows = list(csv.DictReader(open(out / "cases.csv")))
assert len(rows) == 2 and all(r["status"] == "complete" for r in rows), rows
for r in rows:
    assert r["timing_runs"] == "3", r
    lo, med, hi = float(r["solve_seconds_min"]), float(r["solve_seconds_median"]), float(r["solve_seconds_max"])
    assert 0 < lo <= med <= hi, r
    case = out / "cases" / f"{int(r['case']):03d}"
    assert 'name="Write VTK" type="bool" value="false"' in (case / "deck.xml").read_text()
    assert not any((case / "vtk").glob("*.vtu")), "a timing run wrote VTK"
    last = float(r["solve_seconds"])
    assert lo <= last <= hi, (last, r)
report = (out / "report.md").read_text()
assert "each case ran 3 times, one case at a time, without VTK output" in report, report
assert "| lagrange | 1 | 1 |" in report and " - " in report.split("## Cost per group")[1]
bad = subprocess.run([exe, "study", deck, "--output", str(out), "--timing", "0"], capture_output=True, text=True)
assert bad.returncode == 1 and "--timing takes a whole number of runs from 1 to 100" in bad.stderr, bad.stderr
print("ok: timing study ran each case 3 times without VTK; median and range in cases.csv and the report")
