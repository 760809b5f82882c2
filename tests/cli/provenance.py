#!/usr/bin/python3
"""What produced a result (core/Provenance.hpp):
- `beamcontact --version` (and `version`) exits 0 and prints the version core/Version.hpp and the
  top-level CMakeLists.txt state, the commit the source tree's git says HEAD is (12 hex digits,
  "-dirty" allowed; "unknown" outside a git checkout), the build type and compiler CMake configured,
  Trilinos x.y.z and the MPI library whose version `mpirun --version` prints;
- a run of Example 1 carries the same version and commit, the date (UTC, within the test's run), this
  host, the rank count and its command line (quoted as a shell would split it back) in status.txt ("key: value" lines after the status),
  summary.csv (a column each after its figures, quoted as CSV where needed: the figures' columns
  are as before) and effective_parameters.xml (a processing instruction; the file
  parses as XML and runs as a deck to the same tracked_points.csv, byte for byte);
- on 2 ranks status.txt says "ranks: 2";
- cmake/BuildInfo.cmake records "unknown" for a folder inside a checkout (not its top), and for a
  checkout of its own its HEAD, with "-dirty" while a tracked file is changed (not for an untracked one);
- CITATION.cff and CHANGELOG.md's newest entry state the same version (and date), LICENSE and
  CITATION.cff the BSD-3-Clause licence.

    provenance.py BEAMCONTACT SOURCE_DIR WORKDIR BUILD_TYPE "COMPILER_ID VERSION" [MPIEXEC ...]
"""
import csv
import datetime
import hashlib
import os
import re
import shlex
import shutil
import socket
import subprocess
import sys
import xml.etree.ElementTree as ET

exe, src, work = (os.path.abspath(a) for a in sys.argv[1:4])
build_type, compiler, mpiexec = sys.argv[4], sys.argv[5], sys.argv[6:]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
deck = os.path.join(src, "input", "example1.xml")
started = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)


def fail(message):
    sys.exit(f"FAIL: {message}")


def run(*args, cmd=None):
    r = subprocess.run((cmd or [exe]) + list(args), capture_output=True, text=True)
    return r


# The version the sources state, twice (CMake checks that they agree).
version = re.search(r'#define BEAMCONTACT_VERSION "([^"]+)"', open(os.path.join(src, "core", "Version.hpp")).read())[1]
project = re.search(r"project\(BeamContact VERSION ([0-9.]+)", open(os.path.join(src, "CMakeLists.txt")).read())[1]
if version != project:
    fail(f"core/Version.hpp says {version}, CMakeLists.txt {project}")

# The release files state the same version: CITATION.cff, CHANGELOG.md's newest entry (with the
# CITATION.cff's release date); the licence is BSD-3-Clause in LICENSE and CITATION.cff.
citation = open(os.path.join(src, "CITATION.cff")).read()
changelog = open(os.path.join(src, "CHANGELOG.md")).read()
cited = re.search(r"^version: (\S+)$", citation, re.M)
released = re.search(r'^date-released: "?(\d{4}-\d{2}-\d{2})"?$', citation, re.M)
entry = re.search(r"^## \[(\d+\.\d+\.\d+)\] - (\d{4}-\d{2}-\d{2})$", changelog, re.M)
if not cited or cited[1] != version or not entry or entry[1] != version or not released or released[1] != entry[2]:
    fail(f"CITATION.cff (version {cited and cited[1]}, released {released and released[1]}) and CHANGELOG.md's "
         f"newest entry ({entry and entry.groups()}) do not state version {version}")
if not open(os.path.join(src, "LICENSE")).read().startswith("BSD 3-Clause License") or \
        not re.search(r"^license: BSD-3-Clause$", citation, re.M):
    fail("LICENSE or CITATION.cff does not state BSD-3-Clause")
print(f"ok: CITATION.cff and CHANGELOG.md state version {version}, released {entry[2]}; BSD-3-Clause")

# The commit git reports for the source tree, when it is the top of a checkout.
head = None
top = subprocess.run(["git", "-C", src, "rev-parse", "--show-toplevel"], capture_output=True, text=True)
if top.returncode == 0 and os.path.realpath(top.stdout.strip()) == os.path.realpath(src):
    head = subprocess.run(["git", "-C", src, "rev-parse", "--short=12", "HEAD"], capture_output=True,
                          text=True).stdout.strip()

# --version and version: the same text.
r = run("--version")
if r.returncode != 0 or r.stderr:
    fail(f"--version: exit {r.returncode}, stderr {r.stderr!r}")
if run("version").stdout != r.stdout:
    fail("beamcontact version differs from beamcontact --version")
lines = r.stdout.splitlines()
if lines[0] != f"beamcontact {version}":
    fail(f"--version's first line is {lines[0]!r}, expected 'beamcontact {version}'")
build = dict(line.split(": ", 1) for line in lines[1:])
if sorted(build) != sorted(["commit", "build_type", "trilinos", "mpi", "compiler"]):
    fail(f"--version's fields are {sorted(build)}")
commit = build["commit"]
if head is not None:
    if not re.fullmatch(re.escape(head) + r"(-dirty)?", commit):
        fail(f"--version says commit {commit}, the source tree is at {head}")
elif commit != "unknown":
    fail(f"--version says commit {commit} outside a git checkout")
if build["build_type"] != build_type or build["compiler"] != compiler:
    fail(f"--version says {build['build_type']} / {build['compiler']}, CMake configured {build_type} / {compiler}")
if not re.fullmatch(r"\d+\.\d+\.\d+", build["trilinos"]):
    fail(f"trilinos: {build['trilinos']}")
mpirun = subprocess.run(["mpirun", "--version"], capture_output=True, text=True).stdout
mpi_version = re.search(r"(\d+\.\d+\.\d+)", mpirun)
if not mpi_version or mpi_version[1] not in build["mpi"]:
    fail(f"mpi: {build['mpi']!r}, mpirun --version says {mpirun.splitlines()[:1]}")
print(f"ok: --version: {version}, commit {commit}, {build['build_type']}, Trilinos {build['trilinos']}, "
      f"{build['mpi']}, {build['compiler']}")


# cmake/BuildInfo.cmake on other trees: a folder inside a checkout but not its top (a tarball unpacked
# there) is "unknown"; a checkout of its own is its HEAD, "-dirty" with a tracked file changed, clean
# again with it restored, and an untracked file does not count.
def recorded_commit(tree):
    out = os.path.join(work, "BuildInfo.cpp")
    subprocess.run(["cmake", f"-DSOURCE_DIR={tree}", f"-DOUTPUT={out}", "-DBUILD_TYPE=x", "-DCOMPILER=y", "-P",
                    os.path.join(src, "cmake", "BuildInfo.cmake")], check=True)
    text = open(out).read()
    os.remove(out)
    return re.search(r'\{"commit", "([^"]*)"\}', text)[1]


tree = os.path.join(work, "tree")
os.makedirs(tree)
open(os.path.join(tree, "a.txt"), "w").write("a\n")
inside = recorded_commit(tree)
git = ["git", "-C", tree, "-c", "user.name=t", "-c", "user.email=t@example.org"]
subprocess.run(git + ["init", "-q"], check=True)
subprocess.run(git + ["add", "a.txt"], check=True)
subprocess.run(git + ["commit", "-qm", "a"], check=True)
tree_head = subprocess.run(git + ["rev-parse", "--short=12", "HEAD"], capture_output=True, text=True).stdout.strip()
clean = recorded_commit(tree)
open(os.path.join(tree, "a.txt"), "w").write("b\n")
dirty = recorded_commit(tree)
open(os.path.join(tree, "a.txt"), "w").write("a\n")
open(os.path.join(tree, "untracked.txt"), "w").write("u\n")
untracked = recorded_commit(tree)
if (inside, clean, dirty, untracked) != ("unknown", tree_head, tree_head + "-dirty", tree_head):
    fail(f"BuildInfo.cmake: inside a checkout {inside}, clean {clean}, dirty {dirty}, untracked {untracked}; "
         f"HEAD {tree_head}")
print(f"ok: BuildInfo.cmake: unknown inside another checkout, {clean}, {dirty}, untracked files not dirty")


def check_run(out, ranks, command_words):
    """The three files of the results directory `out` carry the same provenance."""
    status = open(os.path.join(out, "status.txt")).read().splitlines()
    if not status[0].startswith("complete: "):
        fail(f"{out}: status {status[0]!r}")
    fields = dict(line.split(": ", 1) for line in status[1:] if ": " in line)
    summary_lines = open(os.path.join(out, "summary.csv")).read().splitlines()
    if len(summary_lines) != 2:
        fail(f"{out}/summary.csv has {len(summary_lines)} lines (a header and a row)")
    row = next(csv.DictReader(open(os.path.join(out, "summary.csv"))))
    columns = {k: v for k, v in row.items() if k in ("version", "commit", "build_type", "trilinos", "mpi",
                                                        "compiler", "date", "host", "ranks", "command",
                                                        "deck_sha256")}
    xml = open(os.path.join(out, "effective_parameters.xml")).read()
    pi = re.search(r"<\?beamcontact(.*?)\?>", xml, re.S)
    if not pi:
        fail(f"{out}/effective_parameters.xml has no <?beamcontact ...?>")
    unescape = {"&quot;": '"', "&lt;": "<", "&gt;": ">", "&amp;": "&"}
    in_xml = {k: re.sub("&(quot|lt|gt|amp);", lambda m: unescape[m[0]], v)
              for k, v in re.findall(r'(\w+)="([^"]*)"', pi[1])}
    for name, got in (("status.txt", fields), ("summary.csv", columns), ("effective_parameters.xml", in_xml)):
        for key in ("version", "commit", "build_type", "trilinos", "mpi", "compiler", "date", "host", "ranks",
                    "command", "deck_sha256"):
            if key not in got:
                fail(f"{out}/{name} has no {key}")
        if got["version"] != version or got["commit"] != commit:
            fail(f"{out}/{name}: version {got['version']}, commit {got['commit']}; --version: {version}, {commit}")
        if any(got[k] != build[k] for k in build):
            fail(f"{out}/{name}: build fields differ from --version: {got}")
        if got != fields:
            fail(f"{out}/{name} and status.txt differ: {got} vs {fields}")
    date = datetime.datetime.strptime(fields["date"], "%Y-%m-%dT%H:%M:%SZ").replace(tzinfo=datetime.timezone.utc)
    now = datetime.datetime.now(datetime.timezone.utc)
    if not started <= date <= now:
        fail(f"date {fields['date']} is not between {started} and {now}")
    if fields["host"] != socket.gethostname() or fields["ranks"] != str(ranks):
        fail(f"host {fields['host']} (this is {socket.gethostname()}), ranks {fields['ranks']} (expected {ranks})")
    if shlex.split(fields["command"]) != command_words:
        fail(f"command {fields['command']!r}, expected {' '.join(command_words)!r}")
    # The digest of the deck the run read (a study keeps a case only if its run read the case's deck).
    digest = hashlib.sha256(open(command_words[2], "rb").read()).hexdigest()
    if fields["deck_sha256"] != digest:
        fail(f"deck_sha256 {fields['deck_sha256']}, the deck's SHA-256 {digest}")
    # The figures come first, as before; the provenance columns after "warnings".
    if summary_lines[0].split(",")[0] != "completed" or summary_lines[0].split(",")[-12] != "warnings":
        fail(f"summary.csv header: {summary_lines[0]}")
    if row["completed"] != "1" or not summary_lines[1].startswith("1,1,50,"):
        fail(f"summary.csv row: {summary_lines[1]}")
    ET.parse(os.path.join(out, "effective_parameters.xml"))  # well-formed XML
    return fields


one = os.path.join(work, "one")
r = run("run", deck, "--output", one, "--quiet")
if r.returncode != 0:
    fail(f"run: exit {r.returncode}: {r.stderr}")
check_run(one, 1, [exe, "run", deck, "--output", one, "--quiet"])
print("ok: status.txt, summary.csv and effective_parameters.xml carry the same provenance as --version")

# effective_parameters.xml with its provenance runs as a deck, to the same results (into a folder
# whose name needs quoting in the command line and escaping in XML).
again = os.path.join(work, "again it's \"quoted\" & <escaped>")
effective = os.path.join(one, "effective_parameters.xml")
r = run("run", effective, "--output", again, "--quiet")
if r.returncode != 0:
    fail(f"effective_parameters.xml as a deck: exit {r.returncode}: {r.stderr}")
check_run(again, 1, [exe, "run", effective, "--output", again, "--quiet"])
if open(os.path.join(one, "tracked_points.csv")).read() != open(os.path.join(again, "tracked_points.csv")).read():
    fail("effective_parameters.xml as a deck gives other tracked_points.csv")
print("ok: effective_parameters.xml runs as a deck to the same tracked_points.csv")

if mpiexec:
    two = os.path.join(work, "two")
    r = run("run", deck, "--output", two, "--quiet", cmd=mpiexec + [exe])
    if r.returncode != 0:
        fail(f"2 ranks: exit {r.returncode}: {r.stderr}")
    check_run(two, 2, [exe, "run", deck, "--output", two, "--quiet"])
    print("ok: on 2 ranks the files say ranks: 2")
