#!/usr/bin/python3
"""Benchmark (not a test): a study's wall time with its cases in the pool of workers (the default)
against a process per case (--process-per-case). Writes a penalty study of Example 1
(input/example1.xml, Penalty, --cases values of the normal penalty parameter from 1e4 to 1e5, evenly
spaced in log; VTK off unless --vtk: a copy of the deck with Output/Write VTK false) and runs `beamcontact study STUDY --parallel N --no-report --quiet`
--repeat times each way, the ways interleaved; prints each run's wall time and CPU time (user + system
of the study and all its processes), the medians, and the machine's load average before and after
(the machine may be shared: the CPU time says what the study needs whatever else runs). Every run
must complete every case, and the two ways' first runs must agree: cases.csv but its measured
columns, and every case's result CSVs and log byte for byte.

Usage: bench_study_pool.py BEAMCONTACT [--cases 100] [--parallel 2] [--repeat 3] [--vtk] [--work DIR]
"""
import argparse
import csv
import os
import resource
import shutil
import statistics
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE1 = os.path.join(HERE, "..", "input", "example1.xml")


def write_study(path, cases, vtk):
    """The study deck at `path`; without `vtk`, its base deck beside it: Example 1 with Output/Write VTK false."""
    values = ", ".join(f"{1e4 * 10 ** (i / max(cases - 1, 1)):.6g}" for i in range(cases))
    base = EXAMPLE1
    if not vtk:
        base = os.path.join(os.path.dirname(path), "example1_no_vtk.xml")
        text = open(EXAMPLE1).read().replace('<ParameterList name="Output">', """<ParameterList name="Output">
    <Parameter name="Write VTK" type="bool" value="false"/>""", 1)
        open(base, "w").write(text)
    with open(path, "w") as f:
        f.write(f"""<ParameterList name="Study">
  <Parameter name="Title" type="string" value="Example 1, {cases} normal penalty parameters"/>
  <Parameter name="Base Deck" type="string" value="{os.path.relpath(base, os.path.dirname(path))}"/>
  <ParameterList name="Cases">
    <ParameterList name="penalty">
      <ParameterList name="strategy">
        <Parameter name="Path" type="string" value="Contact/Enforcement/Type"/>
        <Parameter name="Values" type="Array(string)" value="{{Penalty}}"/>
      </ParameterList>
      <ParameterList name="eps_N">
        <Parameter name="Path" type="string" value="Contact/Enforcement/Penalty/Normal Penalty Parameter"/>
        <Parameter name="Values" type="Array(double)" value="{{{values}}}"/>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Outputs">
    <ParameterList name="F_N"><Parameter name="Contact" type="string" value="Normal Force"/></ParameterList>
  </ParameterList>
</ParameterList>
""")


def children_cpu():
    """CPU seconds (user + system) of the ended children of this script and of theirs (a study's
    workers or case processes, which it waits for)."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def once(exe, study, out, parallel, options):
    shutil.rmtree(out, ignore_errors=True)
    cpu0 = children_cpu()
    t0 = time.perf_counter()
    r = subprocess.run([exe, "study", study, "--output", out, "--parallel", str(parallel), "--no-report", "--quiet",
                        *options], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    cpu = children_cpu() - cpu0
    if r.returncode != 0:
        raise SystemExit(f"bench_study_pool: the study {' '.join(options)} exited with {r.returncode}: {r.stderr}")
    return wall, cpu, results(out)


CASE_FILES = ("steps.csv", "contact_points.csv", "newton.csv", "tracked_points.csv", "reactions.csv", "log.txt")


def results(out):
    """What must not depend on how the cases ran: cases.csv but its measured columns, and each case's
    result CSVs and log as bytes."""
    rows = [{k: v for k, v in row.items() if k not in ("solve_seconds", "peak_memory_mb")}
            for row in csv.DictReader(open(os.path.join(out, "cases.csv")))]
    files = {}
    for case in sorted(os.listdir(os.path.join(out, "cases"))):
        for name in CASE_FILES:
            path = os.path.join(out, "cases", case, name)
            files[f"{case}/{name}"] = open(path, "rb").read() if os.path.exists(path) else None
    return rows, files


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("exe")
    ap.add_argument("--cases", type=int, default=100)
    ap.add_argument("--parallel", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--vtk", action="store_true", help="keep Example 1's VTK output (every step)")
    ap.add_argument("--work", default="bench_study_pool")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    study = os.path.abspath(os.path.join(a.work, "penalty_study.xml"))
    write_study(study, a.cases, a.vtk)
    ways = [("worker pool (default)", []), ("process per case", ["--process-per-case"])]
    times = {name: [] for name, _ in ways}
    found = {}
    load_before = os.getloadavg()
    for _ in range(a.repeat):
        for i, (name, options) in enumerate(ways):
            wall, cpu, r = once(a.exe, study, os.path.join(a.work, f"study{i}"), a.parallel, options)
            times[name].append((wall, cpu))
            found.setdefault(name, r)
            print(f"{name}: {wall:.2f} s, CPU {cpu:.2f} s", flush=True)
    load_after = os.getloadavg()
    (rows, files), (their_rows, their_files) = found[ways[0][0]], found[ways[1][0]]
    if rows != their_rows:
        raise SystemExit("bench_study_pool: the two ways gave different cases.csv (outside the measured columns)")
    differ = [name for name in files if files[name] != their_files.get(name)]
    if differ:
        raise SystemExit(f"bench_study_pool: {len(differ)} case files differ between the two ways: {differ[:5]}")
    print(f"the two ways alike: cases.csv but solve_seconds and peak_memory_mb, and {len(files)} case files "
          f"({', '.join(CASE_FILES)}) byte for byte")
    print(f"{a.cases} cases of Example 1 (Penalty, VTK {'on' if a.vtk else 'off'}), --parallel {a.parallel}, "
          f"medians of {a.repeat} interleaved runs; load average before {load_before[0]:.2f} {load_before[1]:.2f} "
          f"{load_before[2]:.2f}, after {load_after[0]:.2f} {load_after[1]:.2f} {load_after[2]:.2f}")
    print(f"{'cases run':24s} {'median s':>9} {'min s':>7} {'max s':>7} {'per case s':>10} {'CPU s':>7}")
    for name, _ in ways:
        wall = [w for w, _ in times[name]]
        cpu = statistics.median(c for _, c in times[name])
        print(f"{name:24s} {statistics.median(wall):9.2f} {min(wall):7.2f} {max(wall):7.2f} "
              f"{statistics.median(wall) / a.cases:10.3f} {cpu:7.2f}")


if __name__ == "__main__":
    main()
