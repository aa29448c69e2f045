#!/usr/bin/env python3
"""Writes the small seed corpus of the fuzz harnesses into tests/fuzz/seeds/<harness>/.

Tiny valid inputs, one file per case and format: a closed tetrahedron, an open square (two
triangles with a boundary), a quad polygon, a nonmanifold fan (three triangles on one edge), a
Moebius-like non-orientable strip, a sliver (nearly zero-area triangle) and a point cloud. The
files are committed (a few KB in all); rerun after changing a case. The signpost seeds are
written by save() itself: make_signpost_seeds.cpp. The integer seeds are operation sequences
(fuzz_integer.cpp: a mesh byte, then 4 bytes per operation), pseudo-random with fixed seeds.
"""
import math
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
SEEDS = os.path.join(HERE, "seeds")

TET = ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)])
SQUARE = ([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [(0, 1, 2), (0, 2, 3)])
QUAD = ([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)], [(0, 1, 2, 3), (0, 1, 4)])
NONMANIFOLD = ([(0, 0, 0), (1, 0, 0), (0.5, 1, 0), (0.5, -1, 0), (0.5, 0, 1)],
               [(0, 1, 2), (1, 0, 3), (0, 1, 4)])
STRIP = ([(math.cos(a), math.sin(a), z) for a in (0, 2.1, 4.2) for z in (-0.3, 0.3)],
         [(0, 2, 1), (1, 2, 3), (2, 4, 3), (3, 4, 5), (4, 1, 5), (5, 1, 0)])
SLIVER = ([(0, 0, 0), (1, 0, 0), (0.5, 1e-9, 0), (0.5, 1, 0)], [(0, 1, 2), (0, 2, 3), (2, 1, 3)])
MESHES = {"tet": TET, "square": SQUARE, "quad": QUAD, "nonmanifold": NONMANIFOLD,
          "strip": STRIP, "sliver": SLIVER}
CLOUD = [(math.cos(0.7 * i) * (1 + 0.1 * i), math.sin(0.7 * i), 0.05 * i * i % 1.0)
         for i in range(24)]


def fmt(x):
    return repr(float(x))


def write(sub, name, data):
    os.makedirs(os.path.join(SEEDS, sub), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(SEEDS, sub, name), mode) as f:
        f.write(data)


def obj(v, f):
    return "".join(f"v {fmt(x)} {fmt(y)} {fmt(z)}\n" for x, y, z in v) + "".join(
        "f " + " ".join(str(i + 1) for i in face) + "\n" for face in f)


def off(v, f):
    return f"OFF\n{len(v)} {len(f)} 0\n" + "".join(
        f"{fmt(x)} {fmt(y)} {fmt(z)}\n" for x, y, z in v) + "".join(
        f"{len(face)} " + " ".join(map(str, face)) + "\n" for face in f)


def ply_header(v, f, fmtname, vtype="float", itype="int"):
    return (f"ply\nformat {fmtname} 1.0\ncomment seed\nelement vertex {len(v)}\n"
            f"property {vtype} x\nproperty {vtype} y\nproperty {vtype} z\n"
            f"element face {len(f)}\nproperty list uchar {itype} vertex_indices\nend_header\n")


def ply_ascii(v, f):
    return ply_header(v, f, "ascii") + "".join(f"{fmt(x)} {fmt(y)} {fmt(z)}\n" for x, y, z in v) + \
        "".join(f"{len(face)} " + " ".join(map(str, face)) + "\n" for face in f)


def ply_binary(v, f, endian, vtype="float", vcode="f"):
    name = "binary_little_endian" if endian == "<" else "binary_big_endian"
    out = ply_header(v, f, name, vtype).encode()
    for p in v:
        out += struct.pack(endian + 3 * vcode, *p)
    for face in f:
        out += struct.pack(endian + "B" + "i" * len(face), len(face), *face)
    return out


def triangles(v, f):
    for face in f:
        for k in range(1, len(face) - 1):
            yield v[face[0]], v[face[k]], v[face[k + 1]]


def stl_ascii(v, f):
    out = "solid seed\n"
    for a, b, c in triangles(v, f):
        out += "  facet normal 0 0 0\n    outer loop\n"
        for p in (a, b, c):
            out += f"      vertex {fmt(p[0])} {fmt(p[1])} {fmt(p[2])}\n"
        out += "    endloop\n  endfacet\n"
    return out + "endsolid seed\n"


def stl_binary(v, f):
    tris = list(triangles(v, f))
    out = b"binary seed".ljust(80, b" ") + struct.pack("<I", len(tris))
    for a, b, c in tris:
        out += struct.pack("<12fH", 0, 0, 0, *a, *b, *c, 0)
    return out


def main():
    for name, (v, f) in MESHES.items():
        write("obj", name + ".obj", obj(v, f))
        write("off", name + ".off", off(v, f))
        write("ply", name + "_ascii.ply", ply_ascii(v, f))
        write("stl", name + "_ascii.stl", stl_ascii(v, f))
        write("stl", name + "_binary.stl", stl_binary(v, f))
    write("ply", "tet_le.ply", ply_binary(*TET, "<"))
    write("ply", "tet_be.ply", ply_binary(*TET, ">"))
    write("ply", "square_le_double.ply", ply_binary(*SQUARE, "<", "double", "d"))
    write("ply", "cloud_ascii.ply", ply_ascii(CLOUD, []))
    write("obj", "cloud.obj", obj(CLOUD, []))
    write("obj", "extras.obj", "# comment\no thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n"
          "vt 0 0\nvt 1 0\nvt 0 1\ng grp\ns 1\nf 1/1/1 2/2/1 3/3/1\nf -3 -2 -1\n")
    write("off", "noff.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n")
    write("xyz", "cloud.xyz", "".join(f"{fmt(x)} {fmt(y)} {fmt(z)}\n" for x, y, z in CLOUD))
    write("xyz", "cloud_normals.xyz", "# x y z nx ny nz\n" + "".join(
        f"{fmt(x)} {fmt(y)} {fmt(z)} 0 0 1\n" for x, y, z in CLOUD))
    write("values", "values.txt", "# one value per vertex\n1\n-2.5\n3e-7\n0\n")
    write("values", "special.txt", "nan\ninf\n-inf\n1e308\n")
    write("matrix_market", "general.mtx", "%%MatrixMarket matrix coordinate real general\n"
          "% comment\n3 3 4\n1 1 2.0\n2 2 -1\n3 1 0.5\n3 3 4e2\n")
    write("matrix_market", "symmetric.mtx", "%%MatrixMarket matrix coordinate real symmetric\n"
          "2 2 3\n1 1 2\n2 1 -1\n2 2 2\n")
    write("matrix_market", "pattern.mtx", "%%MatrixMarket matrix coordinate pattern general\n"
          "2 3 2\n1 3\n2 1\n")
    write("matrix_market", "skew.mtx", "%%MatrixMarket matrix coordinate integer skew-symmetric\n"
          "3 3 2\n2 1 1\n3 2 -4\n")
    for i in range(6):  # even: the icosphere, odd: the square; 16..56 operations
        r = random.Random(100 + i)
        write("integer", f"ops-{i}.bin",
              bytes([i % 2] + [r.randrange(256) for _ in range(4 * (16 + 8 * i))]))


if __name__ == "__main__":
    main()
