#!/usr/bin/python3
"""A user's folder survives a run and a study byte for byte: a study whose output directory is "." in
a folder of the user's (a photo, a PDF, a report.md, cases/mydata.txt, cases/001/keep.txt) is refused,
naming a foreign file, and with --overwrite runs beside them without touching one; a run into a
folder holding the user's status.txt, summary.csv and timers.txt is refused the same way.

    user_folder.py BEAMCONTACT TINY_STUDY BASE_DECK WORKDIR
"""
import hashlib
import os
import re
import shutil
import subprocess
import sys

exe, study_deck, base_deck, work = (os.path.abspath(a) for a in sys.argv[1:5])
shutil.rmtree(work, ignore_errors=True)
folder = os.path.join(work, "my folder")
os.makedirs(os.path.join(folder, "cases", "001"))
user_files = {
    "photo.jpg": b"\xff\xd8\xff\xe0 a photo",
    "paper.pdf": b"%PDF-1.4 a paper",
    "report.md": b"# my notes\n",
    "cases/mydata.txt": b"1 2 3\n",
    "cases/001/keep.txt": b"keep me\n",
}
for name, data in user_files.items():
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def digests():
    return {n: hashlib.sha256(open(os.path.join(folder, n), "rb").read()).hexdigest() for n in user_files}


before = digests()
# The study deck in the user's folder, writing into "." (the folder itself).
shutil.copy(base_deck, os.path.join(folder, "base.xml"))
text = open(study_deck).read()
text = re.sub(r'name="Base Deck" type="string" value="[^"]*"', 'name="Base Deck" type="string" value="base.xml"', text)
text = text.replace('<ParameterList name="Study">', '<ParameterList name="Study">\n  <Parameter name="Output Directory" type="string" value="."/>', 1)
assert 'value="."' in text, "the study deck has no Study list to put the output directory in"
with open(os.path.join(folder, "study.xml"), "w") as f:
    f.write(text)
user_files["base.xml"] = b""
user_files["study.xml"] = b""
before = digests()

r = subprocess.run([exe, "study", "study.xml", "--no-report"], cwd=folder, capture_output=True, text=True)
assert r.returncode == 1, (r.returncode, r.stdout, r.stderr)
assert re.search(r'study directory "\." holds "[^"]+", which beamcontact did not write', r.stderr), r.stderr
assert digests() == before, "a refused study changed the user's files"
assert not os.path.exists(os.path.join(folder, "cases.csv"))
print("ok: a study into a folder of the user's is refused:", r.stderr.strip())

r = subprocess.run([exe, "study", "study.xml", "--no-report", "--overwrite"], cwd=folder, capture_output=True, text=True)
assert r.returncode in (0, 2), (r.returncode, r.stdout, r.stderr)
assert digests() == before, "a study with --overwrite changed the user's files"
assert os.path.exists(os.path.join(folder, "cases.csv"))
assert os.path.exists(os.path.join(folder, "cases", "001", "status.txt"))
# Run again: the study's own files are replaced, the user's stay.
r = subprocess.run([exe, "study", "study.xml", "--no-report", "--overwrite"], cwd=folder, capture_output=True, text=True)
assert r.returncode in (0, 2), (r.returncode, r.stdout, r.stderr)
assert digests() == before, "a second study with --overwrite changed the user's files"
print(f"ok: with --overwrite the study ran twice beside the user's {len(before)} files, each unchanged")

# A run into a folder whose status.txt, summary.csv and timers.txt are the user's.
results = os.path.join(work, "results")
os.makedirs(results)
for name in ("status.txt", "summary.csv", "timers.txt"):
    with open(os.path.join(results, name), "w") as f:
        f.write("the user's " + name + "\n")
r = subprocess.run([exe, "run", base_deck, "--output", results, "--quiet"], capture_output=True, text=True)
assert r.returncode == 1 and 'holds "status.txt", which beamcontact did not write' in r.stderr, r.stderr
for name in ("status.txt", "summary.csv", "timers.txt"):
    assert open(os.path.join(results, name)).read() == "the user's " + name + "\n", name
print("ok: a run into a folder holding the user's status.txt, summary.csv and timers.txt is refused, files unchanged")
