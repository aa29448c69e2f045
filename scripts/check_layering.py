#!/usr/bin/env python3
"""Fails when the library's include graph breaks its layering or has a cycle.

Layers (a folder may include itself and the ones listed for it, nothing else):
  intrinsic -> (nothing)        fem -> intrinsic         pointcloud -> intrinsic
  solvers/linalg -> intrinsic (types only)
  solvers/scalar -> linalg, fem, intrinsic
  solvers/vector -> scalar, linalg, fem, intrinsic
  solvers/recipes -> every solvers layer, fem, intrinsic, pointcloud
Cycles are checked between units: a unit is a header and its .cpp (x.h + x.cpp), so
a.cpp -> b.h and b.cpp -> a.h is a cycle even though no header includes itself.
"""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIBS = ["intrinsic", "fem", "pointcloud", "solvers"]
ALLOWED = {
    "intrinsic": {"intrinsic"},
    "fem": {"fem", "intrinsic"},
    "pointcloud": {"pointcloud", "intrinsic"},
    "solvers/linalg": {"solvers/linalg", "intrinsic"},
    "solvers/scalar": {"solvers/scalar", "solvers/linalg", "fem", "intrinsic"},
    "solvers/vector": {"solvers/vector", "solvers/scalar", "solvers/linalg", "fem", "intrinsic"},
    "solvers/recipes": {"solvers/recipes", "solvers/vector", "solvers/scalar", "solvers/linalg",
                        "fem", "intrinsic", "pointcloud"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer_of(path):
    for layer in sorted(ALLOWED, key=len, reverse=True):
        if path == layer or path.startswith(layer + "/"):
            return layer
    return None


def main():
    graph = {}
    bad = []
    for lib in LIBS:
        for dirpath, _, names in os.walk(os.path.join(ROOT, lib)):
            for name in names:
                if not name.endswith((".h", ".cpp")):
                    continue
                rel = os.path.relpath(os.path.join(dirpath, name), ROOT)
                layer = layer_of(rel)
                if layer is None:
                    bad.append(f"{rel}: not in a known layer (add it to scripts/check_layering.py)")
                    continue
                unit = os.path.splitext(rel)[0]
                text = open(os.path.join(ROOT, rel), encoding="utf-8").read()
                for inc in INCLUDE.findall(text):
                    if not os.path.exists(os.path.join(ROOT, inc)):
                        continue  # a system or third-party header
                    target = layer_of(inc)
                    if target is None or target not in ALLOWED[layer]:
                        bad.append(f"{rel}: includes {inc} ({target or 'outside the library'}), "
                                   f"which layer {layer} may not use")
                    dep = os.path.splitext(inc)[0]
                    if dep != unit:
                        graph.setdefault(unit, set()).add(dep)
    # cycles between units (iterative DFS, colours)
    colour = {}
    for start in sorted(graph):
        if colour.get(start):
            continue
        stack = [(start, iter(sorted(graph.get(start, ()))))]
        path = [start]
        colour[start] = 1
        while stack:
            node, it = stack[-1]
            nxt = next(it, None)
            if nxt is None:
                colour[node] = 2
                stack.pop()
                path.pop()
                continue
            c = colour.get(nxt, 0)
            if c == 1:
                cycle = path[path.index(nxt):] + [nxt]
                bad.append("include cycle between units: " + " -> ".join(cycle))
            elif c == 0:
                colour[nxt] = 1
                path.append(nxt)
                stack.append((nxt, iter(sorted(graph.get(nxt, ())))))
    for line in bad:
        print(line)
    units = len(set(graph) | {d for ds in graph.values() for d in ds})
    if bad:
        print(f"layering violated: {len(bad)} problem(s) in {units} units")
        return 1
    if units < 50:
        print(f"layering check read only {units} units: the tree is not where it should be")
        return 1
    print(f"layering ok: {units} units, no cycle")
    return 0


if __name__ == "__main__":
    sys.exit(main())
