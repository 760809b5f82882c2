#!/usr/bin/python3
"""The bad-input catalogue: decks and command lines a user can get wrong, each with the exit code and
the message fragment it must produce.

    bad_input.py CATALOGUE BASE_DECK BEAMCONTACT WORKDIR [CASE]

CATALOGUE lines (blank lines and # comments are skipped):
    name | exit code | regex the output must match | edits | arguments | setup | check
  (fields separated by " | "; a field may be empty)
  - edits: "OLD => NEW" pairs separated by ";;", applied to BASE_DECK in order, each to the first
    occurrence of OLD (which must be there); "@nest:N" wraps N nested lists around the Beams list;
    "@text:..." replaces the whole deck ("\\n" for new lines). Empty: the base deck unchanged.
  - arguments: the command line after the executable, with {DECK} (the edited deck) and {OUT}
    (WORKDIR/name), split into words like a shell's (shlex: '' is an empty argument); empty:
    "run {DECK} --output {OUT} --quiet". Leading NAME=VALUE words are set in the environment of the
    run instead (e.g. BC_TEST_PLUGIN=hijack for the test plug-in).
  - {PLUGIN} and {OLD_PLUGIN} (in edits, arguments, setup and check): the test plug-in
    (tests/support/FaultPlugin.cpp) and its copy built against another version, from the environment
    variables BC_FAULT_PLUGIN and BC_OLD_PLUGIN. A first word
    "@limit-as:BYTES" runs the executable with that address-space limit (RLIMIT_AS, as prlimit
    --as), so that allocations fail.
  - setup: a shell command run first (with {OUT}, {DECK}, {BASE} and {EXE}), e.g. to leave files in
    {OUT}.
  - check: a shell command run afterwards that must succeed (e.g. that stale files are gone).
Every case must also: finish within 120 s (a hang fails), print at most one line starting with
"beamcontact:" when it fails, and show no Teuchos exception dump, C++ terminate or Python traceback.
With CASE only that case runs; otherwise all, with a count by verdict.
"""
import os
import re
import resource
import shlex
import subprocess
import sys

catalogue, base_deck, exe, work = (os.path.abspath(a) for a in sys.argv[1:5])
only = sys.argv[5] if len(sys.argv) > 5 else None
with open(base_deck) as f:
    base = f.read()
FORBIDDEN = ["Throw number", "Throw test", "terminate called", "Traceback", "Teuchos::Exceptions", "what():"]


def cases():
    with open(catalogue) as f:
        for n, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            # Fields are separated by a '|' with spaces around it (a '|' in a regex has none).
            fields = [x.strip() for x in re.split(r"(?<= )\|(?= |$)", line)]
            fields += [""] * (7 - len(fields))
            yield n, fields[:7]


def edit(deck, edits, name):
    if not edits:
        return deck
    for e in edits.split(";;"):
        e = e.strip()
        if e.startswith("@text:"):
            deck = e[6:].replace("\\n", "\n")
            continue
        if e.startswith("@nest:"):
            depth = int(e[6:])
            head = "".join(f'<ParameterList name="level {i}">' for i in range(depth))
            tail = "</ParameterList>" * depth
            deck = deck.replace('<ParameterList name="Beams">', head + '<ParameterList name="Beams">', 1)
            deck = deck.replace('<ParameterList name="Supports">', tail + '<ParameterList name="Supports">', 1)
            continue
        if " =>" not in e:
            sys.exit(f"catalogue error in case {name}: {e!r} has no ' => '")
        old, new = e.split(" =>", 1)
        old, new = old.replace("\\n", "\n"), new[1:].replace("\\n", "\n")
        if old not in deck:
            sys.exit(f"catalogue error in case {name}: {old!r} is not in the deck")
        deck = deck.replace(old, new, 1)
    return deck


def run(name, code, pattern, edits, args, setup, post):
    out_dir = os.path.join(work, name)
    deck_path = os.path.join(work, name + ".xml")
    subprocess.run(["rm", "-rf", out_dir])
    subst = lambda s: (s.replace("{DECK}", deck_path).replace("{OUT}", out_dir).replace("{BASE}", base_deck)
                       .replace("{EXE}", exe).replace("{PLUGIN}", os.environ.get("BC_FAULT_PLUGIN", "no-plugin"))
                       .replace("{OLD_PLUGIN}", os.environ.get("BC_OLD_PLUGIN", "no-plugin")))
    with open(deck_path, "w") as f:
        f.write(subst(edit(base, edits, name)))
    if setup:
        subprocess.run(["sh", "-c", subst(setup)], check=True)
    argv = shlex.split(subst(args or "run {DECK} --output {OUT} --quiet"))
    limit = None
    if argv and argv[0].startswith("@limit-as:"):
        limit = int(argv.pop(0)[len("@limit-as:"):])
    preexec = (lambda: resource.setrlimit(resource.RLIMIT_AS, (limit, limit))) if limit else None
    env = dict(os.environ)
    while argv and re.match(r"^[A-Z_][A-Z0-9_]*=", argv[0]):
        key, value = argv.pop(0).split("=", 1)
        env[key] = value
    try:
        r = subprocess.run([exe] + argv, capture_output=True, text=True, timeout=120, cwd=work, env=env,
                           preexec_fn=preexec)
    except subprocess.TimeoutExpired:
        return "hang (no exit within 120 s)"
    text = r.stdout + r.stderr
    problems = []
    if r.returncode != int(code):
        problems.append(f"exit {r.returncode}, expected {code}")
    if not re.search(pattern, text):
        problems.append(f"output does not match {pattern!r}")
    if r.returncode != 0 and sum(1 for l in r.stderr.splitlines() if l.startswith("beamcontact:")) > 1:
        problems.append("more than one error line")
    for bad in FORBIDDEN:
        if bad in text:
            problems.append(f"output holds {bad!r}")
    if post and subprocess.run(["sh", "-c", subst(post)]).returncode != 0:
        problems.append(f"the check afterwards failed: {subst(post)}")
    if problems:
        return "; ".join(problems) + "\n    output: " + text.strip()[-400:].replace("\n", "\n    ")
    return None


os.makedirs(work, exist_ok=True)
failed, total = 0, 0
for n, (name, code, pattern, edits, args, setup, post) in cases():
    if only and name != only:
        continue
    total += 1
    problem = run(name, code, pattern, edits, args, setup, post)
    if problem:
        failed += 1
        print(f"FAIL {name} (line {n}): {problem}")
    else:
        print(f"ok   {name}: exit {code}")
if total == 0:
    sys.exit(f"no case named {only}")
print(f"{total - failed} of {total} cases give the expected exit code and message")
sys.exit(1 if failed else 0)
