#!/usr/bin/python3
"""The counts the docs state are the counts the repository has: the bad-input catalogue's cases
(tests/cli/bad_inputs.txt, one case per line that is neither empty nor a comment) as the README,
docs/faults.md and docs/testing.md state them. A count changed in one place and not the others
fails here, naming the file, its number and the catalogue's. And every page (NAME.md) a deck or a
doc cites exists in the repository (at its path, or in docs/).
Usage: doc_counts.py SOURCE_DIR
"""
import os
import re
import sys

root = sys.argv[1]
with open(os.path.join(root, "tests", "cli", "bad_inputs.txt")) as f:
    cases = sum(1 for line in f if line.strip() and not line.lstrip().startswith("#"))
# Where each file states the count: the number the pattern captures.
STATED = [("README.md", r"`bad_input` \((\d+) bad decks"),
          ("docs/faults.md", r"`tests/cli/bad_inputs.txt`: (\d+) cases"),
          ("docs/testing.md", r"\| bad_input_\* \| bad_input \| (\d+) cases")]
failures = 0
for name, pattern in STATED:
    with open(os.path.join(root, name)) as f:
        found = re.findall(pattern, f.read())
    if not found:
        print(f"{name}: does not state the bad-input count (pattern {pattern!r})")
        failures += 1
    for n in found:
        ok = int(n) == cases
        print(f"{name}: {n} bad-input cases stated, the catalogue has {cases}{'' if ok else ': differs'}")
        failures += not ok

# Every page a deck or a doc cites (NAME.md) is the repository's: at the path given (from the
# repository's root or the citing file's folder) or in docs/ (a deck once cited an EXAMPLES.md the
# repository does not have).
import glob

WRITTEN = {"report.md"}  # what a study writes, not a page
citing = (glob.glob(os.path.join(root, "input", "*.xml")) + glob.glob(os.path.join(root, "input", "studies", "*.xml"))
          + glob.glob(os.path.join(root, "docs", "*.md")) + [os.path.join(root, "README.md")])
for file in sorted(citing):
    with open(file) as f:
        for number, line in enumerate(f, 1):
            for page in re.findall(r"(?<![\w/.-])((?:[\w.-]+/)*[\w.-]+\.md)\b", line):
                places = [os.path.join(root, page), os.path.join(os.path.dirname(file), page),
                          os.path.join(root, "docs", page)]
                if page not in WRITTEN and not any(os.path.isfile(p) for p in places):
                    print(f"{os.path.relpath(file, root)}:{number}: cites {page}, which the repository lacks")
                    failures += 1
if failures:
    sys.exit(f"{failures} count(s) or citation(s) differ from the repository")
print("ok")
