#!/usr/bin/python3
"""The counts the docs state are the counts the repository has: the bad-input catalogue's cases
(tests/cli/bad_inputs.txt, one case per line that is neither empty nor a comment) as the README,
docs/faults.md and docs/testing.md state them. A count changed in one place and not the others
fails here, naming the file, its number and the catalogue's.
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
if failures:
    sys.exit(f"{failures} count(s) differ from the repository")
print("ok")
