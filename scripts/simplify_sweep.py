#!/usr/bin/python3
"""`ifem simplify` on every file of a data folder (default ../shared/data), each with a timeout:
outcome, time, vertices in/out, and the invariants of each result checked from its outputs:

  - the coarse .ifem validates (glued sides agree, every face satisfies the triangle inequality);
  - total area (coarse area / multiplicity) equals the input's (sum of `ifem laplacian`'s lumped
    mass M, computed on the same surface) to 1e-9 relative;
  - Gauss–Bonnet per component of the coarse triangulation: Σ angle defects = 2π·χ;
  - every row of P (--map) is ≥ 0 and sums to 1; every input vertex lies in a coarse face.

A refusal passes only when its message says the input has no surface.

usage: scripts/simplify_sweep.py [--ifem build/examples/ifem] [--data DIR] [--timeout 300]
         [--ratio 0.1 | --vertices 500] [--max-bytes N] [--skip-area]
Exit code 1 when any file failed (crash, timeout, a refusal other than "no surface", or a broken
invariant), 0 otherwise. Prints one table row per file (markdown)."""

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time


def read_ifem(path):
    rows = open(path).read().split("\n")
    if rows[0] != "ifem-simplify 1":
        raise ValueError("not an ifem-simplify 1 file")
    nvc, nf, mult, nv = (int(x) for x in rows[1].split())
    sides = []
    for f in range(nf):
        t = rows[2 + f].split()
        sides += [(int(t[3 * k]), int(t[3 * k + 1]), float(t[3 * k + 2])) for k in range(3)]
    at = 2 + nf
    c2f = [int(x) for x in rows[at:at + nvc]]
    at += nvc
    points = []
    for i in range(nv):
        p = rows[at + i].split()
        points.append((int(p[0]), [float(x) for x in p[1:]]))
    return nvc, nf, mult, sides, c2f, points


def corner_angle(a, b, c):
    """Angle opposite side c in a triangle with sides a, b, c."""
    x = (a * a + b * b - c * c) / (2 * a * b)
    return math.acos(max(-1.0, min(1.0, x)))


def components(nf, sides):
    """Component id of each face (faces joined by glued sides)."""
    parent = list(range(nf))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for h, (_, twin, _) in enumerate(sides):
        if twin >= 0:
            parent[find(h // 3)] = find(twin // 3)
    return [find(f) for f in range(nf)]


def check_coarse(nvc, nf, mult, sides, c2f, points):
    """The coarse triangulation's own invariants; returns (area / mult, [problems])."""
    bad = []
    area = 0.0
    comp = components(nf, sides)
    # per (vertex, component): angle sum minus 2π, plus π per boundary side leaving the vertex
    # (Σ = −2πχ of the component; a vertex in several components counts in each)
    defect, faces, edges = {}, {}, {}
    for f in range(nf):
        a, b, c = lens = tuple(sides[3 * f + k][2] for k in range(3))  # side k: corner k -> k+1
        for x, y, z in ((a, b, c), (b, c, a), (c, a, b)):
            if not x + y - z > 1e-12 * (x + y + z):
                bad.append(f"face {f} fails the triangle inequality")
        s = (a + b + c) / 2
        area += math.sqrt(max(s * (s - a) * (s - b) * (s - c), 0.0))
        r = comp[f]
        faces[r] = faces.get(r, 0) + 1
        for k in range(3):  # corner k: between sides k−1 and k, opposite side k+1
            tail, twin, length = sides[3 * f + k]
            key = (tail, r)
            if key not in defect:
                defect[key] = 2 * math.pi
            defect[key] -= corner_angle(lens[(k + 2) % 3], lens[k], lens[(k + 1) % 3])
            if twin < 0:
                defect[key] -= math.pi
            if twin < 0 or twin > 3 * f + k:
                edges[r] = edges.get(r, 0) + 1
            if twin >= 0:
                nxt = 3 * (twin // 3) + (twin % 3 + 1) % 3
                if sides[twin][1] != 3 * f + k or sides[twin][2] != length or sides[nxt][0] != tail:
                    bad.append(f"halfedge {3 * f + k}: its twin does not glue back")
    total, verts = {}, {}
    for (v, r), d in defect.items():
        total[r] = total.get(r, 0.0) + d
        verts[r] = verts.get(r, 0) + 1
    for r in faces:
        chi = verts[r] - edges[r] + faces[r]
        if abs(total[r] - 2 * math.pi * chi) > 1e-6 * max(1, faces[r]) ** 0.5:
            bad.append(f"Gauss-Bonnet: defects {total[r]:.6g} vs 2πχ = {2 * math.pi * chi:.6g}")
    for v, (face, bary) in enumerate(points):
        if face == -1:
            continue
        if not 0 <= face < nf or min(bary) < 0 or abs(sum(bary) - 1) > 1e-12:
            bad.append(f"input vertex {v}: not a point of a coarse face")
            break
    return area / mult, bad[:5]


def check_map(path, n_rows):
    rows = open(path).read().split("\n")
    rows = [r for r in rows if r]
    if len(rows) != n_rows:
        return [f"map has {len(rows)} rows, not {n_rows}"]
    for i, r in enumerate(rows):
        w = [float(t) for t in r.split()[3:]]
        if min(w) < 0 or abs(sum(w) - 1) > 1e-12:
            return [f"P row {i} = {w}"]
    return []


def input_area(ifem, path, tmp, extra):
    """Σ lumped mass of the input surface (the area simplify must keep)."""
    prefix = os.path.join(tmp, "lap")
    r = subprocess.run([ifem, "laplacian", path, "-o", prefix, "--quiet"] + extra,
                       capture_output=True, text=True)
    if r.returncode != 0:
        return None
    total = 0.0
    with open(prefix + "_M.mtx") as f:
        for line in f:
            if line.startswith("%"):
                continue
            break  # size line
        for line in f:
            total += float(line.split()[2])
    return total


def run_one(ifem, path, args, tmp):
    out, mp = os.path.join(tmp, "c.ifem"), os.path.join(tmp, "m.txt")
    for p in (out, mp):
        if os.path.exists(p):
            os.remove(p)
    target = ["--vertices", str(args.vertices)] if args.vertices else ["--ratio", str(args.ratio)]
    cmd = [ifem, "simplify", path, *target, "-o", out, "--map", mp, "--quiet"]
    t0 = time.time()
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return dict(outcome="TIMEOUT", seconds=time.time() - t0, ok=False)
    seconds = time.time() - t0
    if r.returncode != 0:
        msg = (r.stderr.strip().split("\n") or [""])[-1]
        if r.returncode == 2 and "must be below the input's" in msg:
            return dict(outcome="skipped: not above --vertices", seconds=seconds, ok=True)
        ok = "no surface" in msg
        return dict(outcome=("refused: " if ok else f"FAILED rc={r.returncode}: ") + msg[:90],
                    seconds=seconds, ok=ok)
    line = next((x for x in r.stdout.split("\n") if x.startswith("vertices:")), "")
    vin, vout = line.split()[1], line.split()[3]
    stuck = next((x.split()[0] for x in r.stdout.split("\n") if "could not be removed" in x), "0")
    nvc, nf, mult, sides, c2f, points = read_ifem(out)
    area, bad = check_coarse(nvc, nf, mult, sides, c2f, points)
    bad += check_map(mp, len(points))
    if not args.skip_area:
        a0 = input_area(ifem, path, tmp, [])
        if a0 is None:
            bad.append("ifem laplacian failed on the input")
        elif abs(area - a0) > 1e-9 * a0:
            bad.append(f"area {area:.12g} != input {a0:.12g}")
    return dict(outcome="ok" if not bad else "INVARIANT: " + "; ".join(bad), seconds=seconds,
                ok=not bad, vin=vin, vout=vout, stuck=stuck, mult=mult)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ifem", default=os.path.join(here, "..", "build", "examples", "ifem"))
    ap.add_argument("--data", default=os.path.join(here, "..", "..", "shared", "data"))
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--vertices", type=int, default=0)
    ap.add_argument("--max-bytes", type=int, default=0, help="skip files larger than this")
    ap.add_argument("--skip-area", action="store_true", help="no `ifem laplacian` area check")
    args = ap.parse_args()
    files = []
    for sub in ("meshes", "pointclouds"):
        d = os.path.join(args.data, sub)
        if os.path.isdir(d):
            files += [os.path.join(d, f) for f in sorted(os.listdir(d))]
    if args.max_bytes:
        files = [f for f in files if os.path.getsize(f) <= args.max_bytes]
    print("| file | outcome | s | V in | V out | stuck | mult |\n|---|---|---|---|---|---|---|")
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for f in files:
            r = run_one(args.ifem, f, args, tmp)
            failed += not r["ok"]
            name = os.path.relpath(f, args.data)
            print(f"| {name} | {r['outcome']} | {r['seconds']:.2f} | {r.get('vin', '')} | "
                  f"{r.get('vout', '')} | {r.get('stuck', '')} | {r.get('mult', '')} |",
                  flush=True)
    print(f"\n{len(files)} files, {failed} failed")
    return 1 if failed or not files else 0


if __name__ == "__main__":
    sys.exit(main())
