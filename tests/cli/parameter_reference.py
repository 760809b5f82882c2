#!/usr/bin/python3
"""--print-valid-parameters tells the truth (issue 34 item 8):

    parameter_reference.py BEAMCONTACT WORKDIR

- text, xml and yaml forms list the same parameters with the same type, use and value;
- every parameter line of the text is "NAME : TYPE, default: V", ", required, e.g. V" or
  ", optional, e.g. V", TYPE one the reader knows; bools are true or false; every number is in its
  shortest exact form (one significant digit fewer reads back as another number);
- the examples are valid: decks built from the printed values (every required and optional value is
  used in some deck; only the names of beams the decks refer to are the test's own) pass
  `beamcontact check` and run; a name or geometry the test chose is not taken from the reference;
- the defaults are the reader's: every parameter printed with "default: V" in a list that a run's
  effective_parameters.xml holds has the value V there, and every required or optional parameter a
  deck left out is absent there (an optional value has no default the reader fills in); except what
  a run chooses itself and writes there with the reason as its doc string: Linear Solver/Direct
  Solver, printed as "Automatic", and Linear Solver/Reuse Factorization (optional) with it.
"""
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

exe, work = sys.argv[1], sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, timeout=120)


TYPES = {"int", "double", "bool", "string", "Array(int)", "Array(double)", "Array(string)"}


def shortest(token):
    """Whether the number `token` has no more significant digits than it needs."""
    digits = len(re.sub(r"[eE].*$", "", token).lstrip("+-").replace(".", "").strip("0"))
    if digits <= 1:
        return True
    return float("%.*g" % (digits - 1, float(token))) != float(token)


def numbers(type_, value):
    if type_ in ("double", "int"):
        return [value]
    if type_ in ("Array(double)", "Array(int)"):
        inner = value.strip()[1:-1].strip()
        return [v.strip() for v in inner.split(",")] if inner else []
    return []


# --- The three forms.
r = run("--print-valid-parameters")
check(r.returncode == 0 and r.stderr == "", f"text: exit {r.returncode}, stderr {r.stderr[:200]!r}")
text = {}
stack = []
for line in r.stdout.splitlines():
    m = re.match(r"^( +)(\S.*)/$", line)
    if m:
        depth = len(m.group(1)) // 2
        stack = stack[: depth - 1] + [m.group(2)]
        continue
    m = re.match(r"^( +)(\S[^:]*) : (\S+), (default: |required, e\.g\. |optional, e\.g\. )(.*)$", line)
    if m:
        depth = len(m.group(1)) // 2
        use = m.group(4).split(",")[0].split(":")[0].strip()
        text["/".join(stack[: depth - 1] + [m.group(2)])] = (m.group(3), use, m.group(5))
check(len(text) > 100, f"text: {len(text)} parameter lines read")
check(not re.search(r"^ +\S.* : \S+ = ", r.stdout, re.M) and "<required" not in r.stdout, "text: Teuchos' 'NAME : TYPE = VALUE' form is back")

r = run("--print-valid-parameters", "--format", "xml")
check(r.returncode == 0, f"xml: exit {r.returncode}")
try:
    root = ET.fromstring(r.stdout)
except ET.ParseError as e:
    check(False, f"xml: not XML ({e})")
    root = ET.Element("ParameterList")
ref = {}


def walk(element, path):
    for child in element:
        name = child.get("name")
        if child.tag == "ParameterList":
            walk(child, path + [name])
        else:
            ref["/".join(path + [name])] = (child.get("type"), child.get("use"), child.get("value"))


walk(root, [])
check(ref == text, "xml and text differ: " + str(sorted(set(ref.items()) ^ set(text.items()))[:6]))

try:
    import yaml
except ImportError:
    yaml = None
    print("note: no PyYAML (Debian: python3-yaml); the yaml form is not read back")
if yaml:
    r = run("--print-valid-parameters", "--format=yaml")
    check(r.returncode == 0, f"yaml: exit {r.returncode}")
    from_yaml = {}

    def walk_yaml(node, path):
        for p in node["parameters"]:
            from_yaml["/".join(path + [p["name"]])] = (p["type"], p["use"], p["value"])
        for s in node["sublists"]:
            walk_yaml(s, path + [s["name"]])

    if r.returncode == 0:
        walk_yaml(yaml.safe_load(r.stdout), [])
    check(from_yaml == ref, "yaml and xml differ: " + str(sorted(set(ref.items()) ^ set(from_yaml.items()))[:6]))

r = run("--print-valid-parameters", "--format", "json")
check(r.returncode == 1 and "--format takes text, xml or yaml" in r.stderr, f"--format json: {r.stderr!r}")

for path, (type_, use, value) in ref.items():
    check(type_ in TYPES, f"{path}: type {type_}")
    check(use in ("default", "required", "optional"), f"{path}: use {use}")
    if type_ == "bool":
        check(value in ("true", "false"), f"{path}: bool {value!r}")
    for token in numbers(type_, value):
        check(shortest(token), f"{path}: {token} is longer than it needs to be")

# --- Decks from the printed values.
# A leaf is EX (the printed value at its reference path) or (type, value) of the test's own: the names
# the decks refer to, and geometry that makes the model whole.
EX = object()
PLACEHOLDER = {"Beams": "<beam name>", "Supports": "<support name>", "Loads": "<load name>",
               "Tracked Points": "<point name>", "Pairs": "<pair name>", "Joints": "<joint name>"}


def ref_path(path):
    out = []
    for i, part in enumerate(path):
        out.append(PLACEHOLDER[path[i - 1]] if i and path[i - 1] in PLACEHOLDER else part)
    return "/".join(out)


used = set()


def leaves(tree, path, out):
    for name, v in tree.items():
        if isinstance(v, dict):
            out.append(("list", path + [name]))
            leaves(v, path + [name], out)
        else:
            out.append((v, path + [name]))
    return out


def esc(s):
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def write_deck(name, tree):
    # The path of each list as it is written (for EX look-ups).
    def rec(t, path, depth, list_name):
        pad = "  " * depth
        s = f'{pad}<ParameterList name="{esc(list_name)}">\n'
        for key, v in t.items():
            if isinstance(v, dict):
                s += rec(v, path + [key], depth + 1, key)
                continue
            rp = ref_path(path + [key])
            if v is EX:
                check(rp in ref, f"{name}: the reference has no {rp}")
                type_, _, value = ref.get(rp, ("string", "", ""))
                used.add(rp)
            else:
                type_, value = v
            s += f'{pad}  <Parameter name="{esc(key)}" type="{type_}" value="{esc(value)}"/>\n'
        return s + f"{pad}</ParameterList>\n"

    file = os.path.join(work, name + ".xml")
    with open(file, "w") as f:
        f.write(rec(tree, [], 0, "BeamContact"))
    return file


def name(beam):
    return ("string", beam)


def material():
    return {"Young's Modulus": EX, "Poisson's Ratio": EX}


def straight():  # {0, 0, 0} to {1, 0, 0}, a rectangle
    return {"Start": EX, "End": EX, "Elements": EX, "Section Orientation": EX,
            "Section": {"Width": EX, "Height": EX, "Torsion Constant": EX}, "Material": material()}


def fixed(beam, node):
    return {"Beam": name(beam), "Node": ("string", node)}


decks = {
    # A cantilever: clamped at its end, loaded at its start; explicit load factors, reuse factorization.
    "straight": {
        "Beams": {"a": straight()},
        "Supports": {"clamp": {"Beam": name("a"), "Node": EX, "Load Curve": EX}},
        "Loads": {"tip": {"Point": EX, "Force": ("Array(double)", "{0, 0, -1e-06}"), "Load Curve": EX},
                  "end": {"Beam": name("a"), "Node": EX, "Force": ("Array(double)", "{0, 1e-06, 0}")}},
        "Load Stepping": {"Load Factors": EX},
        "Linear Solver": {"Reuse Factorization": EX, "Reuse Iteration Limit": EX},
        "Output": {"Directory": EX, "VTK At": EX,
                   "Tracked Points": {"start": {"Point": EX, "Reference ux": EX, "Reference uy": EX,
                                                "Reference uz": EX, "Reference Source": EX},
                                      "end": {"Beam": name("a"), "Node": EX}}},
        "Plugins": EX,
        "Plugin SHA-256": EX,
    },
    # A straight beam and a circular polyline from its end, joined there.
    "polyline": {
        "Beams": {"a": straight(),
                  "p": {"Points": EX, "Elements": EX, "Section": {"Shape": ("string", "Circle"), "Radius": EX},
                        "Material": material()}},
        "Supports": {"clamp": {"Point": EX}},
        "Joints": {"j": {"Beam A": name("a"), "Node A": EX, "Beam B": name("p"), "Node B": EX}},
    },
    "arc": {
        "Beams": {"arc": {"Arc": {k: EX for k in ("Centre", "Radius", "Normal", "Reference Direction",
                                                   "Start Angle", "End Angle")},
                          "Elements": EX, "Section": {"Shape": ("string", "Circle"), "Radius": EX},
                          "Material": material()}},
        "Supports": {"clamp": fixed("arc", "start")},
    },
    "helix": {
        "Beams": {"helix": {"Helix": {k: EX for k in ("Axis Point", "Axis Direction", "Radius", "Pitch", "Turns",
                                                       "Reference Direction")},
                            "Elements": EX, "Section": {"Width": EX, "Height": EX}, "Material": material()}},
        "Supports": {"clamp": fixed("helix", "start")},
    },
}
# Two beams crossing 0.05 apart (the sections are 0.1 high), clamped at their ends: a contact pair with
# every strategy's sublist, and All Pairs.
cross = {"Start": ("Array(double)", "{0.5, -0.5, 0.15}"), "End": ("Array(double)", "{0.5, 0.5, 0.15}"),
         "Elements": EX, "Section": {"Width": EX, "Height": EX}, "Material": material()}
two = {"a": straight(), "c": cross}
clamps = {"a0": fixed("a", "start"), "a1": fixed("a", "end"), "c0": fixed("c", "start"), "c1": fixed("c", "end")}
decks["pair"] = {
    "Beams": two, "Supports": clamps,
    "Contact": {"Search Margin": EX, "Pairs": {"p": {"Beam A": name("a"), "Beam B": name("c"),
                                                      "Friction Coefficient": EX}},
                "Enforcement": {"Type": EX, "Penalty": {"Normal Penalty Parameter": EX,
                                                        "Tangential Penalty Parameter": EX},
                                "Lagrange Multiplier": {},
                                "Augmented Lagrange": {"Normal Penalty Parameter": EX,
                                                       "Tangential Penalty Parameter": EX}}},
}
decks["all_pairs"] = {
    "Beams": two, "Supports": clamps,
    "Contact": {"All Pairs": ("bool", "true"), "Friction Coefficient": EX,
                "Enforcement": {"Type": ("string", "Lagrange Multiplier")}},
}

# Every example is in some deck (the beam names the decks refer to are the test's own).
for name_, tree in decks.items():
    file = write_deck(name_, tree)
    r = run("check", file)
    check(r.returncode == 0, f"check {name_}: exit {r.returncode}: {r.stderr.strip()[:300]}")
    out = os.path.join(work, "out_" + name_)
    r = run("run", "-q", "-o", out, file)
    check(r.returncode == 0, f"run {name_}: exit {r.returncode}: {r.stderr.strip()[:300]}")
    decks[name_] = (tree, out)
names = {p for p, (t, u, v) in ref.items() if u != "default" and re.search(r"/(Beam|Beam A|Beam B)$", p)}
missing = sorted(p for p, (t, u, v) in ref.items() if u != "default" and p not in used and p not in names)
check(not missing, f"examples no deck uses: {missing}")


# --- The defaults are the reader's.
def value_of(type_, text_):
    text_ = text_.strip()
    if type_ == "double":
        return float(text_)
    if type_ == "int":
        return int(text_)
    if type_ == "bool":
        return {"true": True, "false": False, "1": True, "0": False}[text_.lower()]
    if type_.startswith("Array("):
        inner = text_[1:-1].strip()
        items = [v.strip() for v in inner.split(",")] if inner else []
        return [value_of(type_[6:-1], v) for v in items]
    return text_


# Resolved by the run (core/LinearSolver.hpp, resolveLinearSolver), each with its reason as the doc string.
CHOSEN_BY_THE_RUN = {"Linear Solver/Direct Solver", "Linear Solver/Reuse Factorization"}
# A parameter another given one replaces: absent from the effective deck (which runs as a deck, and a
# deck may not give both).
REPLACED_BY = {"Load Stepping/Number of Increments": "Load Stepping/Load Factors"}
compared = 0
for name_, (tree, out) in decks.items():
    file = os.path.join(out, "effective_parameters.xml")
    if not os.path.exists(file):
        check(False, f"{name_}: no effective_parameters.xml")
        continue
    effective = {}
    docs = {}
    lists = set()

    def walk_effective(element, path):
        for child in element:
            if child.tag == "ParameterList":
                lists.add(ref_path(path + [child.get("name")]))
                walk_effective(child, path + [child.get("name")])
            elif child.tag == "Parameter":
                effective[ref_path(path + [child.get("name")])] = (child.get("type"), child.get("value"))
                docs[ref_path(path + [child.get("name")])] = child.get("docString", "")

    walk_effective(ET.parse(file).getroot(), [])
    given = {ref_path(p) for kind, p in leaves(tree, [], []) if kind != "list"}
    for path, (type_, use, value) in ref.items():
        parent = path.rsplit("/", 1)[0] if "/" in path else ""
        if parent and parent not in lists:
            continue
        if path in CHOSEN_BY_THE_RUN and path not in given:
            got = effective.get(path)
            check(got is not None and got[0] == type_ and
                  docs.get(path, "").startswith(("chosen by Direct Solver = Automatic", "not given, with a Direct")),
                  f"{name_}: {path}: printed {value!r} ({use}), the run's choice {got} without its reason "
                  f"({docs.get(path)!r})")
            compared += 1
        elif path in REPLACED_BY and REPLACED_BY[path] in given:
            check(path not in effective, f"{name_}: {path} in the effective deck beside {REPLACED_BY[path]}")
        elif use == "default" and path not in given:
            got = effective.get(path)
            check(got is not None and got[0] == type_ and value_of(type_, got[1]) == value_of(type_, value),
                  f"{name_}: {path}: printed default {value!r} ({type_}), the reader's {got}")
            compared += 1
        elif path not in given:
            check(path not in effective, f"{name_}: {path} printed as {use} but the reader filled in "
                  f"{effective.get(path)}")
check(compared > 60, f"only {compared} defaults compared")

print(f"{len(ref)} parameters, {len(used)} examples used in {len(decks)} decks, {compared} defaults compared")
if failures:
    print(f"{len(failures)} failures")
    sys.exit(1)
print("ok")
