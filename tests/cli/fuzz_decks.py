#!/usr/bin/python3
"""A scripted mutation fuzzer over deck loading (`beamcontact check`, which reads, validates and
checks a deck without running it).

    fuzz_decks.py BEAMCONTACT WORKDIR SECONDS SEED DECK [DECK...]

Until SECONDS have passed, takes one of the DECKs, applies 1 to 4 random mutations (cut, repeat or swap
lines; delete, insert or flip characters; replace a value by a hostile one: nan, inf, 1e999, -0,
huge ints, "", "{", markup characters, long strings; rename or duplicate tags and attributes; nest
lists; truncate) and runs `check` on it. Every run must end within 10 s with exit 0 or 1 (never 3 or
a signal), print exactly one "beamcontact:" line when it fails and nothing that looks like an
exception dump. A failing input is kept as WORKDIR/failure_N.xml with its output. The seed makes a
run repeatable.
"""
import os
import random
import re
import subprocess
import sys
import time

exe, work, seconds, seed = os.path.abspath(sys.argv[1]), sys.argv[2], float(sys.argv[3]), int(sys.argv[4])
decks = [open(p).read() for p in sys.argv[5:]]
rng = random.Random(seed)
os.makedirs(work, exist_ok=True)
HOSTILE = ["nan", "-nan", "inf", "-inf", "1e999", "-1e999", "1e-999", "-0", "0", "-1", "2147483648", "-2147483649",
           "99999999999999999999", "1e308", "", " ", "{", "}", "{}", "{,}", "{1,2", "1,2,3", "{1;2;3}", "0x1p3",
           "1.5.2", "true", "TRUE", "yes", "&amp;", "<", ">", "\"", "'", "\\", "a" * 5000, "\u00e9", "1e7", "1e8",
           "10000000", "10000001", "start", "end", "middle", "all", "ux", "Penalty", "Lagrange Multiplier"]
TAGS = ["ParameterList", "Parameter", "Param", "parameterlist", "Validators", "x"]
ATTRS = ["name", "type", "value", "id", "docString", "nam", "typ"]
TYPES = ["int", "double", "bool", "string", "Array(double)", "Array(int)", "Array(string)", "float", "char", ""]
FORBIDDEN = ["Throw number", "terminate called", "Traceback", "what():", "Teuchos::"]


def mutate(text):
    lines = text.split("\n")
    kind = rng.randrange(12)
    if kind == 0 and len(lines) > 2:  # cut a line
        del lines[rng.randrange(len(lines))]
    elif kind == 1:  # repeat a line
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif kind == 2 and len(lines) > 2:  # swap two lines
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    elif kind == 3:  # replace a value
        text = "\n".join(lines)
        values = list(re.finditer(r'value="([^"]*)"', text))
        if values:
            m = rng.choice(values)
            v = rng.choice(HOSTILE).replace('"', "&quot;") if rng.random() < 0.8 else rng.choice(HOSTILE)
            text = text[:m.start(1)] + v + text[m.end(1):]
        return text
    elif kind == 4:  # replace a type
        text = "\n".join(lines)
        types = list(re.finditer(r'type="([^"]*)"', text))
        if types:
            m = rng.choice(types)
            text = text[:m.start(1)] + rng.choice(TYPES) + text[m.end(1):]
        return text
    elif kind == 5:  # rename a tag or attribute
        text = "\n".join(lines)
        words = list(re.finditer(r"\b(ParameterList|Parameter|name|type|value)\b", text))
        if words:
            m = rng.choice(words)
            text = text[:m.start()] + rng.choice(TAGS + ATTRS) + text[m.end():]
        return text
    elif kind == 6:  # delete characters
        text = "\n".join(lines)
        if text:
            i = rng.randrange(len(text))
            text = text[:i] + text[i + rng.randint(1, 20):]
        return text
    elif kind == 7:  # insert characters
        text = "\n".join(lines)
        i = rng.randrange(len(text) + 1)
        return text[:i] + rng.choice(["<", ">", "/>", "\"", "&", "<!--", "-->", "<?", "</ParameterList>",
                                      "<ParameterList name=\"x\">", "\x00", "\xff", " "]) + text[i:]
    elif kind == 8:  # flip a character
        text = "\n".join(lines)
        if text:
            i = rng.randrange(len(text))
            text = text[:i] + chr(rng.randrange(1, 127)) + text[i + 1:]
        return text
    elif kind == 9:  # nest the lists around one
        text = "\n".join(lines)
        depth = rng.choice([2, 31, 33, 200, 5000])
        m = list(re.finditer(r'<ParameterList name="[^"]*">', text))
        if m:
            at = rng.choice(m)
            close = text.find("</ParameterList>", at.end())
            if close > 0:
                text = (text[:at.start()] + '<ParameterList name="n">' * depth + text[at.start():close] +
                        "</ParameterList>" * depth + text[close:])
        return text
    elif kind == 10:  # truncate
        text = "\n".join(lines)
        return text[:rng.randrange(len(text) + 1)]
    else:  # duplicate a sublist
        text = "\n".join(lines)
        m = list(re.finditer(r'<ParameterList name="[^"]*">', text))
        if m:
            at = rng.choice(m)
            close = text.find("</ParameterList>", at.end())
            if close > 0:
                block = text[at.start():close + len("</ParameterList>")]
                text = text[:at.start()] + block + block + text[at.start() + len(block):]
        return text
    return "\n".join(lines)


start = time.time()
runs, failures, verdicts = 0, 0, {0: 0, 1: 0}
while time.time() - start < seconds:
    text = rng.choice(decks)
    for _ in range(rng.randint(1, 4)):
        text = mutate(text)
    path = os.path.join(work, "case.xml")
    with open(path, "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(text)
    runs += 1
    try:
        r = subprocess.run([exe, "check", path], capture_output=True, timeout=10)
        out = (r.stdout + r.stderr).decode("utf-8", "replace")
        problem = None
        if r.returncode not in (0, 1):
            problem = f"exit {r.returncode}"
        elif r.returncode == 1 and sum(1 for l in r.stderr.decode("utf-8", "replace").splitlines()
                                       if l.startswith("beamcontact:")) != 1:
            problem = "not exactly one error line"
        elif any(b in out for b in FORBIDDEN):
            problem = "an exception dump"
        else:
            verdicts[r.returncode] += 1
    except subprocess.TimeoutExpired:
        problem, out = "no exit within 10 s", ""
    if problem:
        failures += 1
        keep = os.path.join(work, f"failure_{failures}.xml")
        os.replace(path, keep)
        print(f"FAIL ({problem}): {keep}\n    {out.strip()[-300:]}")
print(f"{runs} mutated decks in {time.time() - start:.0f} s: {verdicts[1]} refused with one line, {verdicts[0]} accepted, "
      f"{failures} failures")
sys.exit(1 if failures else 0)
