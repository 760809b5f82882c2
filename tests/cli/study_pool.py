#!/usr/bin/python3
"""The study's pool of workers (docs/studies.md, "How the cases run") against a process per case:
- tests/cli/decks/pool_study.xml (10 cases of Example 1: each strategy, six penalty cases, a starved
  case and a misspelt parameter) run both ways, --parallel 2, into study directories of the same name:
  cases.csv equal in every column but solve_seconds and peak_memory_mb; every file of every case equal
  byte for byte (steps, contact points, Newton, tracked points, reactions, VTK, log.txt, the manifest)
  but for the measured figures (summary.csv's *_seconds and peak_memory_mb, timers.txt) and the date
  (status.txt, summary.csv, effective_parameters.xml), so each worker's second and later cases equal
  runs of their own, and each case records the same command line;
- the processes started: 2 by the pool (study.json; no more than 2 children of the study seen while
  it ran, sampled), 10 by a process per case;
- a case whose strategy ends its worker (the fault plug-in's Test Penalty calling std::abort, then
  exit(), in its evaluation; tests/cli/decks/pool_fault_study.xml) is recorded with the status and
  cause a process of its own gets ("failed": "exit code 134"; the line naming the call to exit()),
  the six others complete, and the pool started 3 workers (a new one took the dead one's place);
- a worker killed from outside (SIGKILL) in the middle of a case of tests/cli/decks/slow_study.xml:
  that case "failed" with the cause a case process killed so gets ("exit code 137"), the three others
  complete, 3 workers started, none left running after the study;
- study-worker started by hand (not by a study) refuses in one line, exit 1.
Usage: study_pool.py BEAMCONTACT DECKS_DIR FAULT_PLUGIN WORKDIR"""
import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

exe, decks, plugin, work = sys.argv[1], Path(sys.argv[2]), sys.argv[3], Path(sys.argv[4])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def children(pid):
    """The processes whose parent is `pid` now."""
    found = set()
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            stat = open(f"/proc/{entry}/stat").read()
        except OSError:
            continue
        if int(stat[stat.rindex(")") + 2:].split()[1]) == pid:
            found.add(int(entry))
    return found


def study(deck, where, *options, env=None, watch=None):
    """Runs the study into WHERE/s (cwd WHERE, so both ways write the same paths); returns the process's
    result and the children of the study seen while it ran. `watch(process)` runs beside it."""
    where.mkdir(parents=True, exist_ok=True)
    p = subprocess.Popen([exe, "study", str(deck), "--output", "s", "--parallel", "2", "--no-report", *options],
                         cwd=where, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, **(env or {})))
    seen = set()
    done = threading.Event()

    def sample():
        while not done.is_set():
            seen.update(children(p.pid))
            time.sleep(0.005)

    sampler = threading.Thread(target=sample)
    sampler.start()
    if watch:
        watch(p)
    out, err = p.communicate(timeout=600)
    done.set()
    sampler.join()
    return subprocess.CompletedProcess(p.args, p.returncode, out, err), seen


def rows(where):
    return list(csv.DictReader(open(where / "s" / "cases.csv")))


def started(where):
    meta = json.load(open(where / "s" / "study.json"))
    return meta["case_processes"], meta["processes_started"]


MEASURED = re.compile(r"_seconds$|^peak_memory_mb$|^date$")


def csv_without_measured(path):
    lines = list(csv.reader(open(path)))
    keep = [i for i, name in enumerate(lines[0]) if not MEASURED.search(name)]
    return [[row[i] for i in keep] for row in lines]


def without_date(path):
    return re.sub(r'^(date: |  date=").*$', r"\1", path.read_text(), flags=re.M)


def compare_cases(a, b):
    """Every file of every case folder of study a/s and b/s equal, but for measured figures and the date."""
    compared = 0
    for case in sorted((a / "s" / "cases").iterdir()):
        other = b / "s" / "cases" / case.name
        files = sorted(str(f.relative_to(case)) for f in case.rglob("*") if f.is_file())
        theirs = sorted(str(f.relative_to(other)) for f in other.rglob("*") if f.is_file())
        check(files == theirs, f"case {case.name}: files {files} against {theirs}")
        for name in set(files) & set(theirs):
            mine, their = case / name, other / name
            if name == "timers.txt":
                continue
            if name == "summary.csv":
                same = csv_without_measured(mine) == csv_without_measured(their)
            elif name in ("status.txt", "effective_parameters.xml"):
                same = without_date(mine) == without_date(their)
            else:
                same = mine.read_bytes() == their.read_bytes()
            check(same, f"case {case.name}: {name} differs between the pool and a process per case")
            compared += 1
    return compared


# 1. The same study both ways: the same results.
pool, seen_pool = study(decks / "pool_study.xml", work / "pool")
alone, seen_alone = study(decks / "pool_study.xml", work / "alone", "--process-per-case")
print(pool.stdout, pool.stderr, alone.stdout, alone.stderr)
check(pool.returncode == 2 and alone.returncode == 2, f"exit codes {pool.returncode}, {alone.returncode}, expected 2")
a, b = rows(work / "pool"), rows(work / "alone")
check([r["status"] for r in a].count("complete") == 8, f"pool statuses {[r['status'] for r in a]}")
drop = ("solve_seconds", "peak_memory_mb")
check([{k: v for k, v in r.items() if k not in drop} for r in a] ==
      [{k: v for k, v in r.items() if k not in drop} for r in b], "cases.csv differs between the pool and a process "
      "per case outside the timing columns")
files = compare_cases(work / "pool", work / "alone")
check(files > 100, f"only {files} files compared")
for r in a:
    status = (work / "pool" / "s" / "cases" / f"{int(r['case']):03d}" / "status.txt")
    if status.exists():
        command = [line for line in status.read_text().splitlines() if line.startswith("command: ")]
        check(command == [f"command: {exe} run s/cases/{int(r['case']):03d}/deck.xml --output s/cases/"
                          f"{int(r['case']):03d} --quiet"], f"case {r['case']}: {command}")
check(started(work / "pool") == ("worker pool", 2), f"pool: {started(work / 'pool')}")
check(started(work / "alone") == ("process per case", 10), f"process per case: {started(work / 'alone')}")
check(1 <= len(seen_pool) <= 2, f"the pool's study had {len(seen_pool)} children: {sorted(seen_pool)}")
check(len(seen_alone) <= 10, f"the process-per-case study had {len(seen_alone)} children")
print(f"pool and process per case: {len(a)} cases, {files} files alike; the study's children seen: "
      f"{len(seen_pool)} (pool), {len(seen_alone)} (process per case)")

# 2. A case whose strategy ends its worker: std::abort, then exit().
for mode, expected in (("evaluate-abort", "exit code 134"), ("evaluate-exit", "call to exit() in the middle")):
    env = {"BC_TEST_PLUGIN": mode}
    pool, _ = study(decks / "pool_fault_study.xml", work / mode / "pool", "--plugin", plugin, env=env)
    alone, _ = study(decks / "pool_fault_study.xml", work / mode / "alone", "--plugin", plugin, "--process-per-case",
                     env=env)
    check(pool.returncode == 2 and alone.returncode == 2, f"{mode}: exit codes {pool.returncode}, {alone.returncode}")
    a, b = rows(work / mode / "pool"), rows(work / mode / "alone")
    outcome = [(r["status"], r["cause"], r["F_N"]) for r in a]
    check(outcome == [(r["status"], r["cause"], r["F_N"]) for r in b],
          f"{mode}: the pool recorded {outcome}, a process per case {[(r['status'], r['cause']) for r in b]}")
    check(a[0]["status"] == "failed" and expected in a[0]["cause"], f"{mode}: case 1 {a[0]['status']}: {a[0]['cause']}")
    check([r["status"] for r in a[1:]] == ["complete"] * 6, f"{mode}: {[r['status'] for r in a]}")
    check(started(work / mode / "pool") == ("worker pool", 3), f"{mode}: {started(work / mode / 'pool')}")
    print(f"{mode}: case 1 {a[0]['status']} ({a[0]['cause']}) both ways, 6 complete; pool: 3 workers started")


# 3. A worker killed from outside in the middle of a case.
def kill_first_running(where):
    def watch(p):
        status = where / "s" / "cases" / "001" / "status.txt"
        deadline = time.time() + 120
        text = ""
        while time.time() < deadline and not text.startswith("running (pid "):
            time.sleep(0.01)
            text = status.read_text() if status.exists() else ""
        pid = int(text.split("pid ")[1].split(")")[0])
        os.kill(pid, signal.SIGKILL)
        watch.killed = pid
    return watch


results = {}
for way, options in (("pool", ()), ("alone", ("--process-per-case",))):
    where = work / "kill" / way
    watch = kill_first_running(where)
    run, _ = study(decks / "slow_study.xml", where, *options, watch=watch)
    print(run.stdout, run.stderr)
    check(run.returncode == 2, f"kill, {way}: exit {run.returncode}, expected 2")
    r = rows(where)
    failed = [x for x in r if x["status"] != "complete"]
    check(len(failed) == 1 and len(r) == 4, f"kill, {way}: {[(x['status'], x['cause']) for x in r]}")
    if failed:
        status = (where / "s" / "cases" / f"{int(failed[0]['case']):03d}" / "status.txt").read_text()
        check(status.startswith(f"running (pid {watch.killed})"), f"kill, {way}: the failed case's status {status!r}")
        results[way] = (failed[0]["status"], failed[0]["cause"])
    left = subprocess.run(["pgrep", "-f", str(where / "s" / "cases")], capture_output=True, text=True).stdout.strip()
    check(not left, f"kill, {way}: processes left after the study: {left}")
check(results.get("pool") == results.get("alone") == ("failed", "exit code 137"), f"killed: {results}")
check(started(work / "kill" / "pool") == ("worker pool", 3), f"kill: {started(work / 'kill' / 'pool')}")
print(f"a worker killed in a case: {results.get('pool')} as a case process killed so; 3 workers started")

# 4. study-worker by hand.
r = subprocess.run([exe, "study-worker", str(work)], capture_output=True, text=True, timeout=60)
check(r.returncode == 1 and r.stdout == "" and r.stderr.count("\n") == 1 and "is started by beamcontact study"
      in r.stderr, f"study-worker by hand: {r.returncode} {r.stdout!r} {r.stderr!r}")

if failures:
    sys.exit(f"{len(failures)} failures")
print("ok: the pool's cases equal a process per case's; 2 workers for 10 cases; a worker that aborts, calls "
      "exit() or is killed is recorded as a case process would be and replaced")
