"""`--correspondence signposts|integer`: the two ways refinement keeps inserted vertices on the
input give the same results through every command (distances, Poisson, the common subdivision,
the refined mesh), both save and restore (`ifem refine --save`, read back by `ifem render
--triangulation`), and a bad choice or a bad file is refused with the reason."""

import math

import numpy as np

from clitools import write_obj
from test_cli_render import read_png

KINDS = ("signposts", "integer")


def read_ascii_ply(path):
    """(vertices #V×3, faces #F×3, face properties #F×k) of an ASCII PLY written by ifem."""
    text = path.read_text().split("\n")
    end = text.index("end_header")
    header = text[:end]
    nv = int(next(h for h in header if h.startswith("element vertex")).split()[2])
    nf = int(next(h for h in header if h.startswith("element face")).split()[2])
    v = np.array([[float(x) for x in line.split()[:3]] for line in text[end + 1:end + 1 + nv]])
    rows = [[float(x) for x in line.split()] for line in text[end + 1 + nv:end + 1 + nv + nf]]
    f = np.array([r[1:4] for r in rows], dtype=int)
    props = np.array([r[4:] for r in rows])
    return v, f, props


def boundary_grid(path, n=7):
    """A jittered n×n grid (a disk with boundary, non-Delaunay), as an OBJ file."""
    rng = np.random.default_rng(5)
    verts = [(i / n + 0.3 * rng.uniform(-1, 1) / n, j / n + 0.3 * rng.uniform(-1, 1) / n,
              0.1 * math.sin(3 * i / n) * math.cos(2 * j / n))
             for j in range(n + 1) for i in range(n + 1)]
    faces = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i + 1, j * (n + 1) + i + 2  # OBJ ids are 1-based
            c, d = a + n + 1, b + n + 1
            faces += [(a, b, d), (a, d, c)]
    write_obj(path, verts, faces)
    return path


def test_same_distances_and_poisson(cli):
    o = cli.out
    for mesh in (cli.spot, boundary_grid(o / "grid.obj")):
        d, p = {}, {}
        n = sum(1 for line in open(mesh) if line.startswith("v "))
        (o / "bc.txt").write_text(f"0 0\n{n - 1} 1\n")
        (o / "rhs.txt").write_text("\n".join(str(math.sin(0.1 * i)) for i in range(n)) + "\n")
        for kind in KINDS:
            cli.ok("distance", mesh, "--source", 0, "--refine", "--resolution", 0,
                   "--min-angle", 28, "--correspondence", kind, "-o", o / f"d_{kind}.txt",
                   "--quiet")
            d[kind] = np.loadtxt(o / f"d_{kind}.txt")
            # f carried onto the inserted vertices through the correspondence
            cli.ok("poisson", mesh, "--rhs", o / "rhs.txt", "--dirichlet", o / "bc.txt",
                   "--refine", "--correspondence", kind, "-o", o / f"p_{kind}.txt", "--quiet")
            p[kind] = np.loadtxt(o / f"p_{kind}.txt")
        assert d["signposts"].shape == (n,) and d["signposts"].max() > 0
        assert np.max(np.abs(d["signposts"] - d["integer"])) <= 1e-9, mesh
        assert np.max(np.abs(p["signposts"] - p["integer"])) <= 1e-9, mesh


def test_same_common_subdivision_and_mesh(cli):
    o = cli.out
    out = {}
    for kind in KINDS:
        r = cli.ok("refine", cli.spot, "--min-angle", 28, "--correspondence", kind, "--ascii",
                   "-o", o / f"cs_{kind}.ply", "--mesh", o / f"m_{kind}.ply", "--save",
                   o / f"{kind}.ifem")
        assert f"ifem-{'signpost' if kind == 'signposts' else 'integer'} 1" in r.out, r.describe()
        out[kind] = (read_ascii_ply(o / f"cs_{kind}.ply"), read_ascii_ply(o / f"m_{kind}.ply"))
    (vs, fs, ps), (ms, mfs, _) = out["signposts"]
    (vi, fi, pi), (mi, mfi, _) = out["integer"]
    # the same polygons (intrinsic face ∩ input face), covering the same area
    assert set(map(tuple, ps.astype(int))) == set(map(tuple, pi.astype(int)))

    def area(v, f):
        return 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]),
                                    axis=1).sum()
    assert abs(area(vs, fs) - area(vi, fi)) <= 1e-12 * area(vs, fs)
    # the same refined triangulation, inserted vertices at the same places
    assert np.array_equal(mfs, mfi)
    assert np.max(np.abs(ms - mi)) <= 1e-9
    assert ms.shape[0] > 2930  # vertices were inserted


def blue(rows):
    return sum(p[2] > p[0] + 60 and p[2] > p[1] + 30 for row in rows for p in row)


def test_save_restore_both(cli):
    o = cli.out
    counts = {}
    for kind in KINDS:
        cli.ok("refine", cli.spot, "--correspondence", kind, "--save", o / f"{kind}.ifem",
               "--quiet")
        first = (o / f"{kind}.ifem").read_text().split("\n", 1)[0]
        assert first == ("ifem-signpost 1" if kind == "signposts" else "ifem-integer 1")
        cli.ok("render", cli.spot, "--triangulation", o / f"{kind}.ifem", "--size", "200x150",
               "--colormap", "gray", "-o", o / f"{kind}.png", "--quiet")
        counts[kind] = blue(read_png(o / f"{kind}.png")[2])
    # the same edges traced over the input: the same drawing up to antialiasing
    assert counts["signposts"] > 1000
    assert abs(counts["signposts"] - counts["integer"]) <= 0.02 * counts["signposts"], counts


def test_curves_same_with_both_kinds(cli):
    """Curves with --correspondence integer (FlipOut's steps replayed on integer coordinates):
    the same Poisson values and distances as with signposts."""
    o = cli.out
    (o / "c.txt").write_text("0 764 0 813\n1 1200 2000\n")
    u, d = {}, {}
    for kind in KINDS:
        cli.ok("poisson", cli.spot, "--curves", o / "c.txt", "--refine", "--correspondence",
               kind, "-o", o / f"u_{kind}.txt", "--quiet")
        u[kind] = np.loadtxt(o / f"u_{kind}.txt")
        cli.ok("distance", cli.spot, "--curves", o / "c.txt", "--refine", "--correspondence",
               kind, "-o", o / f"d_{kind}.txt", "--quiet")
        d[kind] = np.loadtxt(o / f"d_{kind}.txt")
    assert np.ptp(u["signposts"]) > 0.5
    assert np.max(np.abs(u["signposts"] - u["integer"])) <= 1e-9
    assert d["signposts"].max() > 0
    assert np.max(np.abs(d["signposts"] - d["integer"])) <= 1e-9


def test_relax_same_with_both_kinds(cli):
    """`refine --relax 2` with integer coordinates: the same refined mesh as with signposts (the
    same moves; vertex positions on the input to 1e-9 of the mesh size), and the same Poisson
    values through `poisson --refine --relax`."""
    o = cli.out
    meshes = {}
    for kind in KINDS:
        cli.ok("refine", cli.spot, "--relax", 2, "--correspondence", kind, "--mesh",
               o / f"r_{kind}.ply", "-o", o / f"cs_{kind}.ply", "--ascii", "--quiet")
        meshes[kind] = read_ascii_ply(o / f"r_{kind}.ply")
        assert (o / f"cs_{kind}.ply").stat().st_size > 0
    (vs, fs, _), (vi, fi, _) = meshes["signposts"], meshes["integer"]
    assert fs.shape == fi.shape and fs.shape[0] > 5000
    assert np.array_equal(fs, fi)
    assert np.max(np.abs(vs - vi)) <= 1e-9 * np.ptp(vs, axis=0).max()
    (o / "bc.txt").write_text("0 0\n100 1\n")
    u = {}
    for kind in KINDS:
        cli.ok("poisson", cli.spot, "--dirichlet", o / "bc.txt", "--refine", "--relax", 1,
               "--correspondence", kind, "-o", o / f"u_{kind}.txt", "--quiet")
        u[kind] = np.loadtxt(o / f"u_{kind}.txt")
    assert np.ptp(u["signposts"]) > 0.5
    assert np.max(np.abs(u["signposts"] - u["integer"])) <= 1e-9


def test_bad_choice_and_bad_files(cli):
    o = cli.out
    cli.refuse(2, r"--correspondence: .*'ints'.*neither 'signposts' nor 'integer'", o / "x.ply",
               "refine", cli.spot, "--correspondence", "ints")
    cli.refuse(2, r"--correspondence", o / "d.txt", "distance", cli.spot, "--source", 0,
               "--refine", "--correspondence", "exact")
    (o / "bad.ifem").write_text("ifem-integer 7\n")
    cli.refuse(1, r"bad\.ifem.*unsupported version 7", o / "x.png", "render", cli.spot,
               "--triangulation", o / "bad.ifem")
    (o / "junk.ifem").write_text("solid cube\n")
    cli.refuse(1, r"junk\.ifem.*not a saved intrinsic triangulation", o / "x.png", "render",
               cli.spot, "--triangulation", o / "junk.ifem")
    cli.ok("refine", cli.spot, "--correspondence", "integer", "--save", o / "cut.ifem",
           "--quiet")
    text = (o / "cut.ifem").read_text()
    (o / "cut.ifem").write_text(text[:len(text) // 2])
    cli.refuse(1, r"cut\.ifem", o / "x.png", "render", cli.spot, "--triangulation",
               o / "cut.ifem")
    # coordinates that pass the per-face checks but do not trace: refused naming the file
    i = text.index("\nedges ")
    m = text.index(" -1\n", i)
    (o / "odd.ifem").write_text(text[:m] + " 1\n" + text[m + 4:])
    cli.refuse(1, r"odd\.ifem: normal coordinates", o / "x.png", "render", cli.spot,
               "--triangulation", o / "odd.ifem")


def flat_grid(path, n=6):
    """A jittered flat n×n grid in z = 0 (linear functions are linear on any triangulation of
    it), as an OBJ file; returns its vertices."""
    rng = np.random.default_rng(9)
    verts = [(i / n + (0.3 * rng.uniform(-1, 1) / n if 0 < i < n else 0),
              j / n + (0.3 * rng.uniform(-1, 1) / n if 0 < j < n else 0), 0.0)
             for j in range(n + 1) for i in range(n + 1)]
    faces = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i + 1, j * (n + 1) + i + 2
            faces += [(a, b, b + n + 1), (a, b + n + 1, a + n + 1)]
    write_obj(path, verts, faces)
    return np.array(verts)


def test_transfer_both_ways_both_kinds(cli):
    o = cli.out
    v = flat_grid(o / "flat.obj")
    f = 0.4 + 1.3 * v[:, 0] - 0.7 * v[:, 1]
    np.savetxt(o / "f.txt", f, fmt="%.17g")
    refine = ("--min-angle", 28, "--max-area", 0.004, "--quiet")
    for kind in KINDS:
        r = cli.ok("refine", o / "flat.obj", "--correspondence", kind, "--mesh",
                   o / f"m_{kind}.ply", "--ascii", *refine)
        x = read_ascii_ply(o / f"m_{kind}.ply")[0]
        for method in ("pointwise", "l2"):
            r = cli.ok("transfer", o / "flat.obj", "--values", o / "f.txt", "--method", method,
                       "--correspondence", kind, "-o", o / "u.txt", *refine)
            u = np.loadtxt(o / "u.txt")
            assert u.shape == (x.shape[0],) and x.shape[0] > v.shape[0]
            assert np.max(np.abs(u - (0.4 + 1.3 * x[:, 0] - 0.7 * x[:, 1]))) <= 1e-9
            before, after = map(float, r.out.split("integral ")[1].split(" -> "))
            assert abs(before - after) <= 1e-10 * abs(before), r.out
            cli.ok("transfer", o / "flat.obj", "--values", o / "u.txt", "--method", method,
                   "--back", "--correspondence", kind, "-o", o / "back.txt", *refine)
            assert np.max(np.abs(np.loadtxt(o / "back.txt") - f)) <= 1e-9
    cli.fails("--method.*'cubic'", "transfer", o / "flat.obj", "--values", o / "f.txt",
              "--method", "cubic", "-o", o / "u.txt")
    cli.fails("expected one per vertex of the refined triangulation", "transfer", o / "flat.obj",
              "--values", o / "back.txt", "--back", "-o", o / "u.txt", "--max-area", 0.004)
    np.savetxt(o / "short.txt", f[:-1])
    cli.fails("expected one per input vertex", "transfer", o / "flat.obj", "--values",
              o / "short.txt", "-o", o / "u.txt")
    h = cli.ok("transfer", "--help").out
    assert "pointwise" in h and "Galerkin" in h and "--back" in h


# every command that refines takes --correspondence (issue 33 item 3; D-330)
REFINING = ("refine", "distance", "eigen", "poisson", "field", "transport", "logmap", "transfer")


def test_integer_is_the_default_everywhere(cli):
    """Integer coordinates by default (D-330): `refine --save` writes 'ifem-integer 1' without
    the option, and every refining command's help names both kinds, integer as the default."""
    o = cli.out
    r = cli.ok("refine", cli.spot, "--min-angle", 20, "--save", o / "default.ifem")
    assert (o / "default.ifem").read_text().split("\n", 1)[0] == "ifem-integer 1"
    assert "ifem-integer 1" in r.out, r.describe()
    for command in REFINING:
        h = cli.ok(command, "--help").out
        i = h.find("--correspondence KIND")  # the option's entry (the prose may name it too)
        assert i >= 0, command
        end = h.find("\n  -", i)  # the next option's entry
        text = " ".join(h[i:end if end > 0 else len(h)].split())
        assert "(default integer" in text, (command, text[:300])
        assert "'signposts'" in text, command
