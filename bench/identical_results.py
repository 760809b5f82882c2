#!/usr/bin/env python3
"""Fingerprints the results of a fixed set of runs, so that a change meant to leave behaviour alone
(a refactoring) can be shown to leave every result file identical to the last printed digit.

Usage:
  identical_results.py BEAMCONTACT WORKDIR [--ranks-only 1|2]   # runs the cases, prints fingerprints
  identical_results.py --compare A.txt B.txt                    # lists the files that differ

A fingerprint is the SHA-256 of each result file. Measured times and memory are left out: timers.txt,
and in CSV files every column whose name holds "seconds", "memory" or "_mb" (summary.csv, study
tables); the checkout's path in study reports. Figures (png, pdf, svg) are left out (their metadata carry dates).
So is the provenance (core/Provenance.hpp: commit, date, host, command line), which differs between
any two builds and runs: its lines in status.txt, the "# " lines of summary.csv, the <?beamcontact?>
instruction of effective_parameters.xml, the commit column of cases.csv, study.json's "provenance"
and report.md's Provenance section. Everything else, the VTK files and the status lines included,
must be byte-identical.

The cases cover the contact layer's paths: the seed paper's three examples (Lagrange multiplier) and
Example 1 with each strategy and with automatic penalties, line contact of parallel rods with each
strategy (the nodal multiplier field with Lagrange multipliers), a cantilever rolled up (no contact),
and generated decks (a strand, a weave and a fibre network) on 1 and 2 ranks.
"""
import csv
import hashlib
import io
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MPI = ["mpirun", "-np", "2", "--oversubscribe"]
WORK = [""]  # the folder of the runs, left out of logs
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}


def with_strategy(text, strategy):
    return re.sub(r'(<ParameterList name="Enforcement">\s*<Parameter name="Type" type="string" value=")[^"]*"',
                  r'\g<1>' + strategy + '"', text, count=1)


def deck_variants(work):
    """(name, deck path, ranks) of every run."""
    decks = []

    def variant(name, source, edit=None):
        with open(source) as f:
            text = f.read()
        if edit:
            text = edit(text)
        path = os.path.join(work, "decks", name + ".xml")
        with open(path, "w") as f:
            f.write(text)
        return path

    inp = os.path.join(ROOT, "input")
    for ex in ("example1", "example2", "example3"):
        decks.append((ex, os.path.join(inp, ex + ".xml"), 1))
    decks.append(("example1_np2", os.path.join(inp, "example1.xml"), 2))
    for tag, strategy in (("penalty", "Penalty"), ("al", "Augmented Lagrange")):
        decks.append(("example1_" + tag, variant("example1_" + tag, os.path.join(inp, "example1.xml"),
                                                 lambda t, s=strategy: with_strategy(t, s)), 1))
    for tag, strategy in (("penalty", "Penalty"), ("lm", "Lagrange Multiplier"), ("al", "Augmented Lagrange")):
        decks.append(("rods_" + tag, variant("rods_" + tag, os.path.join(inp, "parallel_rods.xml"),
                                             lambda t, s=strategy: with_strategy(t, s)), 1))
    decks.append(("rods_lm_np2", os.path.join(work, "decks", "rods_lm.xml"), 2))
    decks.append(("roll_up", os.path.join(inp, "cantilever_roll_up.xml"), 1))
    return decks


def generated(beamcontact, work):
    out = []
    for kind, args in (("strand", []), ("weave", ["--n", "4", "--m", "4"]), ("network", ["--fibres", "20"])):
        path = os.path.join(work, "decks", kind + ".xml")
        subprocess.run([beamcontact, "generate", kind, *args, "--overwrite", "--output", path], check=True,
                       stdout=subprocess.DEVNULL)
        out += [(kind, path, 1), (kind + "_np2", path, 2)]
    return out


def fingerprint_file(path):
    name = os.path.basename(path)
    if name == "timers.txt" or name.endswith((".png", ".pdf", ".svg")):
        return None
    with open(path, "rb") as f:
        data = f.read()
    data = without_provenance(name, data)
    if name.endswith(".csv"):
        rows = list(csv.reader(io.StringIO(data.decode())))
        if rows:
            keep = [i for i, h in enumerate(rows[0])
                    if not any(w in h for w in ("seconds", "memory", "_mb")) and h != "commit"]
            buf = io.StringIO()
            w = csv.writer(buf, lineterminator="\n")
            for r in rows:
                w.writerow([r[i] for i in keep if i < len(r)])
            data = buf.getvalue().encode()
    elif name.endswith(".md"):
        data = markdown_without_times(data.decode()).encode()
    if name.endswith((".md", ".json")):
        data = data.replace(ROOT.encode(), b"ROOT")  # study reports name the deck by its path
    elif name == "log.txt":
        data = re.sub(rb"solve [0-9.e+-]+ s", b"solve - s", data)
        data = data.replace(WORK[0].encode(), b"WORK")
    return hashlib.sha256(data).hexdigest()


PROVENANCE_KEYS = ("version", "commit", "build_type", "trilinos", "mpi", "compiler", "date", "host", "ranks",
                   "command")


def without_provenance(name, data):
    """A results file without its provenance (core/Provenance.hpp)."""
    text = data.decode(errors="replace")
    if name == "status.txt":
        lines = text.splitlines(True)
        text = "".join(lines[:1] + [l for l in lines[1:] if l.split(": ", 1)[0] not in PROVENANCE_KEYS])
    elif name == "summary.csv":
        text = "".join(l for l in text.splitlines(True) if not l.startswith("# "))
    elif name == "effective_parameters.xml":
        text = re.sub(r"<\?beamcontact\b.*?\?>\n", "", text, flags=re.S)
    elif name == "report.md":
        text = text.split("## Provenance")[0]
    elif name == "study.json":
        text = re.sub(r',\n  "provenance": \{.*?\}\n', "\n", text, flags=re.S)
    else:
        return data
    return text.encode()


def markdown_without_times(text):
    """A study report without the columns of measured times (headers with "[s]")."""
    out, drop = [], []
    for line in text.splitlines():
        if line.startswith("|"):
            cells = line.strip().strip("|").split("|")
            if not drop and any("[s]" in c for c in cells):
                drop = [i for i, c in enumerate(cells) if "[s]" in c]
            out.append("|".join(c for i, c in enumerate(cells) if i not in drop))
        else:
            drop = []
            out.append(line)
    return "\n".join(out)


def fingerprints(folder, tag):
    lines = []
    for dirpath, _, files in os.walk(folder):
        for f in sorted(files):
            p = os.path.join(dirpath, f)
            h = fingerprint_file(p)
            if h:
                lines.append(f"{tag}/{os.path.relpath(p, folder)} {h}")
    return sorted(lines)


def run_all(beamcontact, work, ranks_only):
    WORK[0] = work
    if os.path.exists(work):
        shutil.rmtree(work)
    os.makedirs(os.path.join(work, "decks"))
    lines = []
    env = dict(os.environ, **MPI_ENV)
    for name, deck, ranks in deck_variants(work) + generated(beamcontact, work):
        if ranks_only and ranks != ranks_only:
            continue
        out = os.path.join(work, name)
        cmd = ([*MPI] if ranks == 2 else []) + [beamcontact, "run", deck, "--output", out, "--quiet"]
        r = subprocess.run(cmd, env=env, capture_output=True, text=True)
        lines.append(f"{name}/exit {r.returncode}")
        lines += fingerprints(out, name)
        print(f"{name}: exit {r.returncode}", file=sys.stderr)
    study = os.path.join(ROOT, "input", "studies", "automatic_penalty_example1.xml")
    if not ranks_only or ranks_only == 1:
        out = os.path.join(work, "study")
        r = subprocess.run([beamcontact, "study", study, "--output", out], env=env, capture_output=True, text=True)
        lines.append(f"study/exit {r.returncode}")
        lines += fingerprints(out, "study")
        print(f"study: exit {r.returncode}", file=sys.stderr)
    return lines


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--compare":
        a = dict(l.rsplit(" ", 1) for l in open(sys.argv[2]).read().splitlines() if " " in l)
        b = dict(l.rsplit(" ", 1) for l in open(sys.argv[3]).read().splitlines() if " " in l)
        differ = sorted(k for k in a.keys() | b.keys() if a.get(k) != b.get(k))
        for k in differ:
            print("differs:", k)
        print(f"{len(a)} fingerprints, {len(differ)} differ")
        sys.exit(1 if differ else 0)
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ranks_only = int(sys.argv[4]) if len(sys.argv) == 5 and sys.argv[3] == "--ranks-only" else 0
    for line in run_all(os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2]), ranks_only):
        print(line)


if __name__ == "__main__":
    main()
