#!/usr/bin/python3
"""An error on one MPI rank only ends every rank: each place where a rank can fail alone (reading the
deck, loading a plug-in, its registration, the strategy's constructor, the assembly inside Newton, the
linear solve, the output) is made to fail on rank 1 of a 2-rank run of Example 1, which must end within
10 s with the failing rank's message and a non-zero exit code.

    rank_faults.py MPIEXEC BEAMCONTACT PLUGIN DECK WORKDIR

Faults come from the test plug-in (tests/support/FaultPlugin.cpp, BC_TEST_PLUGIN=MODE@1) and from the
program's test hook (BEAMCONTACT_INJECT_FAULT=place:1, core/Faults.hpp). Prints each case's time.
"""
import os
import re
import subprocess
import sys
import time

mpiexec, exe, plugin, deck, work = sys.argv[1:6]
os.makedirs(work, exist_ok=True)
with open(deck) as f:
    base = f.read()
# The deck with the plug-in's strategy (the built-in Penalty under the name "Test Penalty").
test_deck = os.path.join(work, "test_penalty.xml")
with open(test_deck, "w") as f:
    f.write(base.replace('value="Lagrange Multiplier"/>', 'value="Test Penalty"/>', 1)
            .replace('<ParameterList name="Penalty">', '<ParameterList name="Test Penalty">', 1))

LIMIT = 10.0
cases = [
    # name, environment, deck, message expected from rank 1
    ("deck", {"BEAMCONTACT_INJECT_FAULT": "deck:1"}, deck, r"injected fault at deck on rank 1"),
    ("plugin load", {"BEAMCONTACT_INJECT_FAULT": "plugin:1"}, deck, r"injected fault at plugin on rank 1"),
    ("plugin registration", {"BC_TEST_PLUGIN": "register-fail@1"}, deck, r"failed while registering: registration failed on purpose"),
    ("strategy constructor", {"BC_TEST_PLUGIN": "construct-fail@1"}, test_deck, r"Test Penalty's constructor failed on purpose"),
    ("strategy evaluation in Newton", {"BC_TEST_PLUGIN": "evaluate-fail@1"}, test_deck, r"Test Penalty's evaluation failed on purpose"),
    ("assembly", {"BEAMCONTACT_INJECT_FAULT": "assembly:1"}, deck, r"injected fault at assembly on rank 1"),
    ("linear solve", {"BEAMCONTACT_INJECT_FAULT": "solve:1"}, deck, r"injected fault at solve on rank 1"),
    ("output", {"BEAMCONTACT_INJECT_FAULT": "output:1"}, deck, r"injected fault at output on rank 1"),
    # Newton's step changed on rank 1 alone (no exception): the ranks would converge or fail apart and
    # the run hang in the next collective; they stop together at the first such step.
    ("diverging step", {"BEAMCONTACT_INJECT_FAULT": "step:1"}, deck, r"the ranks computed different Newton steps"),
]
failed = 0
for name, extra, d, pattern in cases:
    out = os.path.join(work, re.sub(r"\W+", "_", name))
    subprocess.run(["rm", "-rf", out])
    env = dict(os.environ, **extra)
    cmd = mpiexec.split(";") + [exe, "run", d, "--output", out, "--quiet", "--plugin", plugin]
    t0 = time.monotonic()
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=env)
        seconds, code, text = time.monotonic() - t0, r.returncode, r.stdout + r.stderr
    except subprocess.TimeoutExpired:
        seconds, code, text = 60.0, None, "(hung: killed after 60 s)"
    problems = []
    if code is None or seconds > LIMIT:
        problems.append(f"took {seconds:.1f} s (limit {LIMIT:.0f} s)")
    if code == 0:
        problems.append("exit code 0")
    if not re.search(pattern, text):
        problems.append(f"no message matching {pattern!r}")
    if sum(1 for l in text.splitlines() if l.startswith("beamcontact:")) > 1:
        problems.append("more than one error line")
    verdict = "FAIL" if problems else "ok  "
    print(f"{verdict} {name:32s} {seconds:5.2f} s  exit {code}  " + "; ".join(problems))
    if problems:
        failed += 1
        print("     output: " + text.strip()[-600:].replace("\n", "\n     "))
print(f"{len(cases) - failed} of {len(cases)} rank-1 faults end every rank within {LIMIT:.0f} s")
sys.exit(1 if failed else 0)
