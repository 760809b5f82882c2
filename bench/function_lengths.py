#!/usr/bin/env python3
"""Lines per function body and per source file, for the size rules in docs/architecture.md
(no function over 100 lines, at most 8 over 60, no source file over 900 lines).

Usage: function_lengths.py [ROOT] [--top N]

A function is a brace block opened at namespace level (outside classes) after a line holding "(",
or a member function body defined inside a class; its length counts the lines from its signature's
last line to the closing brace. Comments and string literals are skipped when braces are counted.
"""
import os
import re
import sys

FOLDERS = ("core", "constraints", "elements", "input", "drivers")


def strip(text):
    """The text with comments, strings and characters blanked (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif text.startswith('R"(', i):
            j = text.find(')"', i + 3)
            j = n if j < 0 else j + 2
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path):
    text = strip(open(path, encoding="utf-8", errors="replace").read())
    found = []
    stack = []  # kinds of the open braces: "ns", "class", "fn", "block"
    line = 1
    start = {}
    last = 0  # position after the last ; { or }
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c == "{":
            head = text[last:i]
            inside_fn = "fn" in stack
            if inside_fn:
                kind = "block"
            elif re.search(r"\bnamespace\b[^()]*$", head) or re.search(r'extern\s+""\s*$', head):
                kind = "ns"
            elif re.search(r"\b(class|struct|union|enum)\b[^()]*$", head):
                kind = "class"
            elif "(" in head and not re.search(r"=\s*$", head):
                kind = "fn"
                name = re.findall(r"([~\w:<>]+)\s*\(", head)
                start[len(stack)] = (line, name[0] if name else "?")
            else:
                kind = "block"
            stack.append(kind)
            last = i + 1
        elif c == "}":
            if stack:
                kind = stack.pop()
                if kind == "fn":
                    first, name = start.pop(len(stack))
                    found.append((line - first + 1, name, first))
            last = i + 1
        elif c == ";":
            last = i + 1
    return found, line


def main():
    args = sys.argv[1:]
    top = 10
    if "--top" in args:
        k = args.index("--top")
        top = int(args[k + 1])
        del args[k:k + 2]
    root = args[0] if args else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    funcs, files = [], []
    for folder in FOLDERS:
        for dirpath, _, names in os.walk(os.path.join(root, folder)):
            for f in names:
                if f.endswith((".cpp", ".hpp")):
                    p = os.path.join(dirpath, f)
                    found, lines = functions(p)
                    rel = os.path.relpath(p, root)
                    files.append((lines - 1, rel))
                    funcs += [(n, name, f"{rel}:{first}") for n, name, first in found]
    funcs.sort(reverse=True)
    files.sort(reverse=True)
    print(f"functions over 100 lines: {sum(1 for f in funcs if f[0] > 100)}, over 60: "
          f"{sum(1 for f in funcs if f[0] > 60)}; files over 900 lines: {sum(1 for f in files if f[0] > 900)}")
    print("longest functions:")
    for n, name, where in funcs[:top]:
        print(f"  {n:5d}  {name}  {where}")
    print("largest files:")
    for n, rel in files[:top]:
        print(f"  {n:5d}  {rel}")


if __name__ == "__main__":
    main()
