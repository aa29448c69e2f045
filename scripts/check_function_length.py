#!/usr/bin/env python3
"""Fails when a function in intrinsic/ fem/ solvers/ pointcloud/ examples/ is longer than
MAX_LINES lines (from the first line of its signature, template head included, to its closing
brace) unless a comment line starting `// Long function:` stands in the comment block right
above it, giving the reason. Prints every offender (path:line, name, length), longest first.

Functions are found with the brace-scope tracker of check_naming.py (a regex scan, not a
compiler): definitions at namespace or class scope, with their bodies; lambdas and local classes
count towards the function that contains them.

Usage: scripts/check_function_length.py [--max N] [folders...]
"""
import argparse
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_naming import ROOT, strip_code, strip_templates, top_level_index  # noqa: E402

FOLDERS = ["intrinsic", "fem", "solvers", "pointcloud", "examples"]
MAX_LINES = 80
WAIVER = re.compile(r"^\s*//\s*Long function:")


def waived(lines, first):
    """True when the comment block right above line `first` (1-based) has a waiver line."""
    k = first - 2
    while k >= 0 and lines[k].strip().startswith("//"):
        if WAIVER.match(lines[k]):
            return True
        k -= 1
    return False


def skip_braces(code, i, line):
    """From the "{" at code[i]: the index past its matching "}" and the line number there."""
    depth, j = 1, i + 1
    while j < len(code) and depth:
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
        elif code[j] == "\n":
            line += 1
        j += 1
    return j, line


def functions(code):
    """(name, first line, last line) of every function definition in stripped code."""
    out = []
    stack = ["ns"]
    stmt, stmt_line, line, parens = [], 1, 1, 0
    i, n = 0, len(code)
    while i < n:
        c = code[i]
        if c == "\n":
            line += 1
        if c in "([":
            parens += 1
        elif c in ")]":
            parens = max(0, parens - 1)
        if parens > 0 or c not in "{};":
            if not stmt and c.isspace():
                stmt_line = line + (1 if c == "\n" else 0)
            else:
                if not stmt:
                    stmt_line = line
                stmt.append(c)
            i += 1
            continue
        if c == ";":
            stmt = []
            i += 1
            continue
        if c == "}":
            if len(stack) > 1:
                stack.pop()
            stmt = []
            i += 1
            continue
        head = " ".join(strip_templates("".join(stmt)).split())
        start = stmt_line
        stmt = []
        if re.match(r"^(inline\s+)?namespace\b|^extern\b", head):
            stack.append("ns")
        elif re.match(r"^(template\s*)?(class|struct|union|enum)\b", head) and "(" not in head:
            stack.append("ns")  # a class scope: its member functions are found the same way
        elif "(" in head and "=" not in head[: max(0, top_level_index(head, "("))]:
            m = re.search(r"([~\w:]+|operator\s*\S+)\s*$", head[: top_level_index(head, "(")])
            name = m.group(1) if m else "?"
            i, line = skip_braces(code, i, line)
            out.append((name, start, line))
            continue
        else:
            # initializer, control block or anything else: skip its braces
            i, line = skip_braces(code, i, line)
            continue
        i += 1
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--max", type=int, default=MAX_LINES)
    ap.add_argument("folders", nargs="*", default=FOLDERS)
    args = ap.parse_args()
    files = subprocess.run(["git", "ls-files", "--", *args.folders], cwd=ROOT, check=True,
                           capture_output=True, text=True).stdout.split()
    files = [f for f in files if f.endswith((".h", ".cpp"))]
    offenders = []
    for path in files:
        with open(os.path.join(ROOT, path), encoding="utf-8") as f:
            text = f.read()
        lines = text.split("\n")
        for name, first, last in functions(strip_code(text)):
            length = last - first + 1
            if length > args.max and not waived(lines, first):
                offenders.append((length, path, first, name))
    offenders.sort(key=lambda o: (-o[0], o[1], o[2]))
    for length, path, first, name in offenders:
        print(f"{path}:{first}: {name} is {length} lines (> {args.max})")
    if offenders:
        print(f"function length: {len(offenders)} function(s) over {args.max} lines without a "
              "'// Long function: <reason>' comment right above")
        return 1
    print(f"function length ok ({len(files)} files, max {args.max} lines)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
