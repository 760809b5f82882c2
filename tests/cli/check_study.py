"""Runs the tiny study (tests/cli/decks/tiny_study.xml) and checks what it wrote:
- exit code 2 (some case did not complete) and every case recorded in cases.csv;
- the starved case "incomplete" with the run's cause, the misspelt path an "input error" naming it;
- each complete case's outputs equal its own results at T = 1 (tracked_points.csv, the sum of the
  normal forces of contact_points.csv) and A's deflection within 8 % of the paper's Table 1
  (9.79-9.89);
- the errors against the reference group (the Lagrange case): each output's error and relative
  error equal the differences of the cases' own values;
- report.md with the table, the plots as non-empty PNG and PDF (the error plot on log-log axes
  with its fitted slope), the load-displacement curves and Newton histories, and each run's
  newton.csv (the residual history) with the iterations steps.csv counts;
- run again into the same directory, the three complete cases are kept untouched (their summary.csv
  not rewritten) and the two others run again; a stale case directory (cases/099) is removed."""
import csv
import math
import subprocess
import sys
from pathlib import Path

exe, deck, out = sys.argv[1], sys.argv[2], Path(sys.argv[3])
subprocess.run(["rm", "-rf", str(out)])
run = subprocess.run([exe, "study", deck, "--output", str(out), "--parallel", "2"], capture_output=True, text=True)
print(run.stdout)
print(run.stderr)
assert run.returncode == 2, f"exit code {run.returncode}, expected 2"
assert "4/5" in run.stdout and "5/5" in run.stdout, "no progress counter"

rows = list(csv.DictReader(open(out / "cases.csv")))
assert [r["group"] for r in rows] == ["lagrange", "penalty", "penalty", "starved", "typo"], rows
status = {r["case"]: r["status"] for r in rows}
assert status == {"1": "complete", "2": "complete", "3": "complete", "4": "incomplete", "5": "input error"}, status
assert "Maximum Iterations" in rows[3]["cause"], rows[3]["cause"]
assert "Normal Penalty Parametr" in rows[4]["cause"], rows[4]["cause"]
assert rows[3]["A uz"] == "" and rows[3]["F_N"] == "", "a case that did not reach T = 1 must have no outputs"

for r in rows[:3]:
    case = out / "cases" / f"{int(r['case']):03d}"
    tracked = list(csv.DictReader(open(case / "tracked_points.csv")))
    last = tracked[-1]
    assert float(last["T"]) == 1.0
    assert float(r["A uz"]) == float(last["A_uz"]), (r["A uz"], last["A_uz"])
    points = [p for p in csv.DictReader(open(case / "contact_points.csv")) if p["step"] == last["step"] and p["active"] == "1"]
    total = sum(float(p["normal_force"]) for p in points)
    assert math.isclose(float(r["F_N"]), total, rel_tol=1e-9), (r["F_N"], total)
    assert abs(-float(r["A uz"]) - 9.85) < 0.08 * 9.85, r["A uz"]
    assert int(r["newton_iterations"]) >= 50 and float(r["solve_seconds"]) > 0, r

ref = rows[0]
for r in rows[:3]:
    for o in ("A uz", "F_N"):
        e = float(r[o]) - float(ref[o])
        assert math.isclose(float(r[o + " error"]), e, rel_tol=1e-9, abs_tol=1e-12), (o, r[o + " error"], e)
        assert math.isclose(float(r[o + " relative error"]), e / abs(float(ref[o])), rel_tol=1e-9, abs_tol=1e-15)
assert rows[3]["A uz error"] == "" and rows[3]["A uz relative error"] == "", "an incomplete case has no error"
for r in rows[:3]:
    case = out / "cases" / f"{int(r['case']):03d}"
    steps = list(csv.DictReader(open(case / "steps.csv")))
    newton = list(csv.DictReader(open(case / "newton.csv")))
    for s in steps:
        iterates = [n for n in newton if n["step"] == s["step"]]
        # One iterate per Newton iteration, and the converged one (the end of a pass is where the next
        # pass starts, with the updated multipliers or active set).
        assert len(iterates) == int(s["newton_iterations"]) + 1, (case, s, len(iterates))
    assert float(newton[-1]["residual_norm"]) < float(newton[0]["residual_norm"]) or len(newton) == 1

report = (out / "report.md").read_text()
assert "| case | group |" in report and "Cases that did not complete" in report
png = out / "F_N_vs_eps_N.png"
data = png.read_bytes()
assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, len(data)
assert "![F_N vs eps_N](F_N_vs_eps_N.png) ([PDF](F_N_vs_eps_N.pdf))" in report
for stem in ("F_N_vs_eps_N", "A_uz_error_vs_eps_N", "curve_A_uz", "newton_per_step"):
    assert (out / (stem + ".pdf")).read_bytes()[:5] == b"%PDF-", stem
    assert (out / (stem + ".png")).stat().st_size > 5000, stem
assert "## Relative error against \"lagrange\"" in report and "## What was varied" in report
assert "Timings are indicative" in report
import json  # noqa: E402
meta = json.load(open(out / "study.json"))
error_plot = [p for p in meta["plots"] if p["name"] == "A uz error vs eps_N"][0]
assert error_plot["published_x"] == [2e4] and error_plot["published_y"] == [-9.79], error_plot
assert error_plot["relative_to"] == "lagrange" and error_plot["error"], error_plot
stamps = {c: (out / "cases" / c / "summary.csv").stat().st_mtime_ns for c in ("001", "002", "003")}
# One study at a time in a directory: a second one while the first holds it is refused.
import fcntl  # noqa: E402
with open(out / "beamcontact-manifest.txt") as held:
    fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
    busy = subprocess.run([exe, "study", deck, "--output", str(out)], capture_output=True, text=True)
assert busy.returncode == 1 and "is in use by another beamcontact study" in busy.stderr, busy.stderr
# A file of the user's in the study directory: the rerun is refused, naming it, and nothing changes.
(out / "cases" / "mine.txt").write_text("user data\n")
refused = subprocess.run([exe, "study", deck, "--output", str(out), "--parallel", "2"], capture_output=True, text=True)
assert refused.returncode == 1, refused.returncode
assert 'holds "cases/mine.txt", which beamcontact did not write' in refused.stderr, refused.stderr
assert (out / "cases" / "mine.txt").read_text() == "user data\n"
assert all((out / "cases" / c / "summary.csv").stat().st_mtime_ns == t for c, t in stamps.items())
(out / "cases" / "mine.txt").unlink()
# A case folder of an earlier, larger study (named in the manifests): the rerun removes it.
(out / "cases" / "099").mkdir()
(out / "cases" / "099" / "deck.xml").write_text("<ParameterList/>\n")
manifest_header = (out / "beamcontact-manifest.txt").read_text().splitlines()[0]
(out / "cases" / "099" / "beamcontact-manifest.txt").write_text(manifest_header + "\ndeck.xml\n")
with open(out / "beamcontact-manifest.txt", "a") as m:
    m.write("cases/099/\n")
again = subprocess.run([exe, "study", deck, "--output", str(out), "--parallel", "2"], capture_output=True, text=True)
print(again.stdout)
assert again.returncode == 2, f"rerun exit code {again.returncode}"
assert "(3 complete from an earlier run, kept)" in again.stdout, again.stdout
assert all((out / "cases" / c / "summary.csv").stat().st_mtime_ns == t for c, t in stamps.items()), "a kept case was rerun"
assert not (out / "cases" / "099").exists(), "stale case directory left"
assert [r["status"] for r in csv.DictReader(open(out / "cases.csv"))] == list(status.values())
print("ok: study recorded 5 cases (3 complete, 1 incomplete, 1 input error), report and plot written; "
      "a rerun kept the 3 complete cases")
