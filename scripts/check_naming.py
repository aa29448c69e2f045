#!/usr/bin/env python3
"""Checks the names that the repo's style rules fix (see docs/decisions.md, "Naming check"):

  files                      snake_case.h / snake_case.cpp
  namespaces                 snake_case
  classes, structs, enums,   CamelCase
  type aliases (using X =)
  enumerators                kCamelCase
  constants (constexpr, or   kCamelCase
  const at namespace scope)
  functions                  snake_case (constructors, destructors, operators and ALL_CAPS
                             macros such as TEST(...) excepted)
  data members               snake_case; in a class's private/protected part with a trailing _
  variables at namespace     snake_case
  scope

Math capitals are allowed in functions and variables (L, M, K, A, X, Lff, solve_L): a name fails
only on a camelCase hump (fooBar) or a capitalized word of three or more letters (Foo, FooBar).
Function bodies are not looked into (local variables and parameters are left to review).

Declarations are found by regex over the tracked .h/.cpp files (tests/data excluded) with a
small brace-scope tracker, not a compiler: cheap (well under a second), and a false positive can
be fixed by renaming or reported as a bug here. Exit status 1 and one line per offender when a
name breaks a rule.
"""
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SNAKE_FILE = re.compile(r"^[a-z0-9_]+\.(h|cpp)$")
SNAKE = re.compile(r"^[a-z][a-z0-9_]*$")
CAMEL = re.compile(r"^[A-Z][A-Za-z0-9]*$")
K_CAMEL = re.compile(r"^k[A-Z][A-Za-z0-9]*$")
MACRO = re.compile(r"^[A-Z][A-Z0-9_]*$")
IDENT = re.compile(r"[A-Za-z_]\w*")


def math_ok(name):
    """snake_case, allowing math capitals but no camelCase humps or capitalized words."""
    if not re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", name):
        return False
    if re.search(r"[a-z][A-Z]", name):
        return False
    return not any(re.match(r"^[A-Z][a-z]{2,}", part) for part in name.split("_"))


def strip_code(text):
    """Removes comments, string and char literals and preprocessor lines (keeping newlines)."""
    out = []
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":
            # preprocessor directive, with line continuations
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append("\n")
                    i += 2
                    continue
                i += 1
            continue
        if c == "/" and text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
            continue
        if c == "/" and text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
            continue
        if c == "R" and text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            if m:
                end = text.find(")" + m.group(1) + '"', i)
                end = n if end < 0 else end + len(m.group(1)) + 2
                out.append('""' + "\n" * text.count("\n", i, end))
                i = end
                continue
        if c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():  # digit separator 1'000
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
            continue
        out.append(c)
        if c == "\n":
            at_line_start = True
        elif not c.isspace():
            at_line_start = False
        i += 1
    return "".join(out)


def strip_templates(s):
    """Drops template<...> heads and every <...> argument list (balanced)."""
    out, depth = [], 0
    i = 0
    while i < len(s):
        c = s[i]
        if c == "<" and not s.startswith("<<", i) and not s.startswith("<=", i) and depth >= 0:
            # a template bracket when preceded by an identifier or 'template'
            prev = s[:i].rstrip()
            if prev and (prev[-1].isalnum() or prev[-1] in "_>:"):
                depth += 1
                i += 1
                continue
        if c == ">" and depth > 0:
            depth -= 1
            i += 1
            continue
        if depth == 0:
            out.append(c)
        i += 1
    return "".join(out)


def top_level_split(s, sep):
    parts, depth, cur = [], 0, []
    for c in s:
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        if c == sep and depth == 0:
            parts.append("".join(cur))
            cur = []
        else:
            cur.append(c)
    parts.append("".join(cur))
    return parts


def top_level_index(s, chars):
    depth = 0
    for i, c in enumerate(s):
        if c in "([{":
            if depth == 0 and c in chars:
                return i
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif depth == 0 and c in chars:
            return i
    return -1


class Checker:
    def __init__(self):
        self.errors = []

    def bad(self, path, line, kind, name, rule):
        self.errors.append(f"{path}:{line}: {kind} '{name}' should be {rule}")

    def check_file(self, path):
        base = os.path.basename(path)
        if not SNAKE_FILE.match(base):
            self.bad(path, 1, "file", base, "snake_case")
        with open(os.path.join(ROOT, path), encoding="utf-8") as f:
            code = strip_code(f.read())
        # scope stack entries: (kind, name, access) with kind in ns/class/enum/block
        stack = [("ns", "", "public")]
        stmt, stmt_line = [], 1
        line = 1
        i, n = 0, len(code)
        parens = 0
        while i < n:
            c = code[i]
            if c == "\n":
                line += 1
            kind = stack[-1][0]
            if kind != "block":
                if c in "([":
                    parens += 1
                elif c in ")]":
                    parens = max(0, parens - 1)
                if parens > 0:
                    stmt.append(c)
                    i += 1
                    continue
            if kind == "block":
                if c == "{":
                    stack.append(("block", "", ""))
                elif c == "}":
                    stack.pop()
                    stmt, stmt_line = [], line
                i += 1
                continue
            if c in "{;}":
                text = "".join(stmt).strip()
                if c == "{":
                    self.open_scope(path, stmt_line, text, stack)
                elif c == ";":
                    self.statement(path, stmt_line, text, stack)
                else:  # }
                    if kind == "enum":
                        self.enumerators(path, stmt_line, text)
                    if len(stack) > 1:
                        stack.pop()
                stmt, stmt_line = [], line
                i += 1
                continue
            if c == ":" and stack[-1][0] == "class" and not stmt_has_content(stmt, ":"):
                spec = "".join(stmt).strip()
                if spec in ("public", "private", "protected"):
                    k, nm, _ = stack[-1]
                    stack[-1] = (k, nm, spec)
                    stmt, stmt_line = [], line
                    i += 1
                    continue
            if not stmt and c.isspace():
                stmt_line = line + (1 if c == "\n" else 0)
                i += 1
                continue
            if not stmt:
                stmt_line = line
            stmt.append(c)
            i += 1

    def open_scope(self, path, line, text, stack):
        kind = stack[-1][0]
        flat = " ".join(text.split())
        m = re.match(r"^(inline\s+)?namespace\s*([\w:]*)$", flat)
        if m:
            for part in filter(None, m.group(2).split("::")):
                if not SNAKE.match(part):
                    self.bad(path, line, "namespace", part, "snake_case")
            stack.append(("ns", m.group(2), "public"))
            return
        if flat.startswith("extern"):
            stack.append(("ns", "", "public"))
            return
        body = strip_templates(flat)
        m = re.match(r"^(?:typedef\s+)?enum(?:\s+(?:class|struct))?\s+(\w+)?\s*(?::[\w\s:]+)?$", body)
        if m:
            if m.group(1) and not CAMEL.match(m.group(1)):
                self.bad(path, line, "enum", m.group(1), "CamelCase")
            stack.append(("enum", m.group(1) or "", "public"))
            return
        m = re.match(r"^(?:template\s*)?(class|struct|union)\s+(?:alignas\s*\(\w+\)\s*)?"
                     r"((?:\w+::)*\w+)\s*(?:final\s*)?(?::[^:].*)?$", body)
        if m and "(" not in body.split(":")[0] and "=" not in body:
            name = m.group(2).split("::")[-1]
            if not CAMEL.match(name):
                self.bad(path, line, m.group(1), name, "CamelCase")
            stack.append(("class", name, "private" if m.group(1) == "class" else "public"))
            return
        if re.match(r"^(struct|class|union)$", body) or re.match(r"^(struct|class|union)\s*:", body):
            stack.append(("class", "", "public"))  # anonymous
            return
        if kind in ("ns", "class") and "(" in body and "=" not in body.split("(")[0]:
            self.function(path, line, body, stack)
        stack.append(("block", "", ""))

    def statement(self, path, line, text, stack):
        kind, cls, access = stack[-1]
        if kind not in ("ns", "class"):
            return
        flat = " ".join(strip_templates(text).split())
        if not flat:
            return
        first = flat.split()[0]
        if first in ("return", "friend", "typedef", "static_assert", "template", "extern",
                     "break", "continue", "goto"):
            return
        m = re.match(r"^using\s+(\w+)\s*=", flat)
        if m:
            if not CAMEL.match(m.group(1)):
                self.bad(path, line, "type alias", m.group(1), "CamelCase")
            return
        if first in ("using", "namespace"):
            return
        if re.match(r"^(class|struct|union|enum)(\s+(class|struct))?\s+\w+$", flat):
            return  # forward declaration
        eq = top_level_index(flat, "={")
        paren = top_level_index(flat, "(")
        if paren >= 0 and (eq < 0 or paren < eq):
            self.function(path, line, flat, stack)
            return
        self.variables(path, line, flat, stack)

    def function(self, path, line, flat, stack):
        kind, cls, _ = stack[-1]
        head = flat[: top_level_index(flat, "(")] if "(" in flat else flat
        if "operator" in head:
            return
        m = re.search(r"(~?[A-Za-z_]\w*)\s*$", head)
        if not m:
            return
        full = re.search(r"([\w:~]+)\s*$", head).group(1)
        name = m.group(1)
        qualifier = full.split("::")[-2] if "::" in full else cls
        if name.lstrip("~") == qualifier or MACRO.match(name):
            return
        if re.search(r"\)\s*(const\s*)?(noexcept\s*)?override\b", flat):
            return  # overrides a base class's (e.g. GoogleTest's SetUp) name
        if name in ("if", "for", "while", "switch", "catch", "return", "sizeof", "decltype",
                    "alignas", "static_assert", "defined"):
            return
        if not SNAKE.match(name) and not math_ok(name):
            self.bad(path, line, "function", name, "snake_case")

    def variables(self, path, line, flat, stack):
        kind, cls, access = stack[-1]
        words = flat.split()
        is_const = "constexpr" in words or (kind == "ns" and "const" in words and
                                            "*" not in flat.split("=")[0].split("const")[-1])
        for k, decl in enumerate(top_level_split(flat, ",")):
            cut = top_level_index(decl, "={")
            decl = decl if cut < 0 else decl[:cut]
            decl = re.sub(r"\[[^\]]*\]", "", decl).strip()
            decl = re.sub(r":\s*\d+$", "", decl).strip()  # bit-field
            ids = IDENT.findall(decl)
            if not ids:
                continue
            name = ids[-1] if k == 0 else ids[0]
            if k == 0 and len(ids) < 2:
                continue  # not a declaration (e.g. a macro call)
            if name in ("const", "override", "final", "default", "delete"):
                continue
            if is_const or (K_CAMEL.match(name) and "const" in words):
                if not K_CAMEL.match(name):
                    self.bad(path, line, "constant", name, "kCamelCase")
            elif kind == "class" and access in ("private", "protected"):
                if not (name.endswith("_") and math_ok(name[:-1])):
                    self.bad(path, line, "private member", name, "snake_case with a trailing _")
            elif not math_ok(name) or name.endswith("_") and kind != "class":
                self.bad(path, line, "member" if kind == "class" else "variable", name,
                         "snake_case")

    def enumerators(self, path, line, text):
        for part in top_level_split(" ".join(text.split()), ","):
            part = part.split("=")[0].strip()
            if part and not K_CAMEL.match(part):
                self.bad(path, line, "enumerator", part, "kCamelCase")


def stmt_has_content(stmt, ch):
    return ch in stmt


def main():
    files = subprocess.run(["git", "ls-files", "*.h", "*.cpp"], cwd=ROOT, check=True,
                           capture_output=True, text=True).stdout.split()
    files = [f for f in files if not f.startswith("tests/data/")]
    checker = Checker()
    for f in files:
        checker.check_file(f)
    for e in checker.errors:
        print(e)
    if checker.errors:
        print(f"naming violated: {len(checker.errors)} name(s) (rules: scripts/check_naming.py)")
        return 1
    print(f"naming ok ({len(files)} files)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
