"""Tangent fields from the command line: `ifem field` (Poincaré–Hopf on spot, unit vectors,
constraints, refusals), `ifem transport` / `ifem logmap` (the log map on a flat grid against
the plane's; transport on a flat L, exact at its corners, refined too), and all three on the frame path (point clouds, a nonmanifold mesh, spot forced
onto the tufted cover)."""

import math
import re
import struct

from clitools import SPOT_VERTICES, count_lines, face_components, grep, head_bytes, lines, \
    obj_faces, obj_vertices, write_obj


def vectors(path):
    return [tuple(float(t) for t in line.split()) for line in lines(path)]


def norm(v):
    return math.sqrt(sum(x * x for x in v[:3]))


# field: Poincaré–Hopf on spot (genus 0: total index 2 for vectors, 8 quarter turns for
# crosses), unit tangent vectors in the .txt (one line per input vertex), a constraints file,
# and the refusals (--align-boundary on a point cloud, a bad line)
def test_field(cli):
    o, spot = cli.out, cli.spot
    r = cli.ok("field", spot, "--symmetry", 4, "-o", o / "fc.ply", "--quiet")
    assert grep("total index 8/4", r.out), r.describe()
    # the input faces' indices: a face property after the index list
    header = head_bytes(o / "fc.ply", 700).split("\n")
    k = next(i for i, t in enumerate(header) if t.startswith("element face 5856"))
    assert any(t.startswith("property double singularity") for t in header[k:k + 3]), header
    r = cli.ok("field", spot, "-o", o / "fv.txt", "--quiet")
    assert grep("total index 2/1", r.out), r.describe()
    assert count_lines(o / "fv.txt") == SPOT_VERTICES
    for v in vectors(o / "fv.txt"):
        assert 1 - 1e-9 <= norm(v) <= 1 + 1e-9, v
    (o / "fcon.txt").write_text("# vertex and direction\n0 1 0 0\n")
    r = cli.ok("field", spot, "--constraints", o / "fcon.txt", "-o", o / "fk.ply", "--quiet")
    assert grep("total index 2/1", r.out), r.describe()
    cli.ok("field", cli.fan3, "--align-boundary", "-o", o / "ff.ply", "--quiet")  # tufted
    r = cli.run("field", cli.spot_points("f_cloud.xyz"), "--align-boundary", "-o",
                o / "ff.ply", "--quiet")
    assert r.rc != 0, r.describe()
    assert grep("align_boundary needs a mesh's faces: a point cloud has no boundary", r.err), \
        r.describe()
    r = cli.run("field", cli.fan3, "--refine", "--resolution", 0.2, "-o", o / "fl.txt", "--quiet")
    assert r.rc != 0, r.describe()
    assert grep("a direction field on the tufted path uses frames from the input's positions"
                ".*do not refine", r.err), r.describe()
    (o / "fbad.txt").write_text("0 1 0\n")
    r = cli.run("field", spot, "--constraints", o / "fbad.txt", "-o", o / "fb.ply", "--quiet")
    assert r.rc != 0, r.describe()
    assert grep("fbad.txt:1: expected 'VERTEX X Y Z'", r.err), r.describe()
    assert not (o / "fb.ply").exists()


# transport / logmap: on a flat grid the log map's radius is the distance to the source (within
# the heat method's error) and (u, v) turn like the plane: the points at ±x from the source
# come out opposite; transported vectors are tangent and keep the length; refusals
def test_vector_heat(cli):
    o = cli.out
    n = 20
    grid = o / "vh_grid.obj"
    with open(grid, "w") as f:
        for j in range(n + 1):
            for i in range(n + 1):
                f.write(f"v {i / n:.6g} {j / n:.6g} 0\n")
        for j in range(n):
            for i in range(n):
                a = j * (n + 1) + i + 1
                f.write(f"f {a} {a + 1} {a + n + 2}\nf {a} {a + n + 2} {a + n + 1}\n")
    lm = o / "vh_lm.txt"
    r = cli.ok("logmap", grid, "--source", 220, "-o", lm, "--quiet")
    assert grep("log map about vertex 220", r.out), r.describe()
    assert count_lines(lm) == 441
    uv = vectors(lm)
    assert uv[220][0] == 0 and uv[220][1] == 0, uv[220]
    for k, (u, v) in enumerate(p[:2] for p in uv):
        x, y = (k % 21) / 20 - 0.5, (k // 21) / 20 - 0.5
        assert abs(math.hypot(u, v) - math.hypot(x, y)) <= 0.06, (k, u, v)
    assert uv[230][0] * uv[210][0] + uv[230][1] * uv[210][1] <= -0.2 * 0.24, (uv[230], uv[210])
    t = o / "vh_t.txt"
    r = cli.ok("transport", cli.spot, "--source", 0, "--vector", "0,0,2", "-o", t, "--quiet")
    assert grep("2930 tangent vectors", r.out), r.describe()
    for v in vectors(t):
        assert 0.5 <= norm(v) <= 2.0 + 1e-9, v
    r = cli.run("transport", cli.spot, "--source", 0, "--vector", "1,0", "-o", o / "vh_bad.txt",
                "--quiet")
    assert r.rc != 0, r.describe()
    assert grep("expected three finite numbers", r.err), r.describe()
    r = cli.run("logmap", cli.spot, "--source", 5000, "-o", o / "vh_bad.txt", "--quiet")
    assert r.rc != 0, r.describe()
    assert not (o / "vh_bad.txt").exists()


def write_flat_l(path, n=12, seed=3):
    """The flat L (the unit square less its top-right quarter) as an OBJ: n×n cells split along
    a diagonal, interior vertices jittered by up to 0.3/n, boundary vertices slid along their
    straight sides; corners of π/2 and one of 3π/2 at (½, ½). Returns the vertex count."""
    rng = seed

    def rnd():
        nonlocal rng
        rng = (rng * 1103515245 + 12345) % 2 ** 31
        return 0.6 * (rng / 2 ** 31 - 0.5) / n

    def kept(i, j):
        return 0 <= i < n and 0 <= j < n and (i < n // 2 or j < n // 2)

    ids, lines_out = {}, []
    for j in range(n + 1):
        for i in range(n + 1):
            c = [kept(i - 1, j - 1), kept(i, j - 1), kept(i - 1, j), kept(i, j)]
            if not any(c):
                continue
            x, y = i / n, j / n
            dx, dy = rnd(), rnd()
            if all(c):
                x, y = x + dx, y + dy
            elif sum(c) == 2 and c[0] == c[2] and c[1] == c[3]:
                y += dy
            elif sum(c) == 2 and c[0] == c[1] and c[2] == c[3]:
                x += dx
            ids[(i, j)] = len(ids) + 1
            lines_out.append(f"v {x:.17g} {y:.17g} 0\n")
    for j in range(n):
        for i in range(n):
            if kept(i, j):
                a, b = ids[(i, j)], ids[(i + 1, j)]
                c, d = ids[(i + 1, j + 1)], ids[(i, j + 1)]
                lines_out.append(f"f {a} {b} {c}\nf {a} {c} {d}\n")
    with open(path, "w") as f:
        f.writelines(lines_out)
    return len(ids)


# transport on a flat L: boundary vertices keep their true angles, so the connection is flat
# and the transported vector is the source's (projected to z = 0, length kept) at EVERY vertex,
# the six corners included (round-off only: 1e-7 covers the text output); a cross field along
# the boundary fits every corner: the constant cross, total index 0
def test_transport_flat_l(cli):
    o = cli.out
    mesh = o / "flat_l.obj"
    nv = write_flat_l(mesh)
    for source, vec in ((0, (0.6, -0.8, 0.5)), (nv // 2, (-1.0, 0.3, 0.0)), (nv - 1, (0, 2, 1))):
        t = o / f"flat_l_t{source}.txt"
        cli.ok("transport", mesh, "--source", source, "--vector", ",".join(map(str, vec)),
               "-o", t, "--quiet")
        got = vectors(t)
        assert len(got) == nv
        for k, v in enumerate(got):
            assert max(abs(v[0] - vec[0]), abs(v[1] - vec[1]), abs(v[2])) <= 1e-7, (source, k, v)
    r = cli.ok("field", mesh, "--symmetry", 4, "--align-boundary", "-o", o / "flat_l_f.txt",
               "--quiet")
    assert grep("total index 0/4", r.out), r.describe()
    for k, v in enumerate(vectors(o / "flat_l_f.txt")):
        a = 4 * math.atan2(v[1], v[0])
        assert abs(math.cos(a) - 1) + abs(math.sin(a)) <= 1e-7, (k, v)


# the same after intrinsic Delaunay refinement (--refine --resolution 0.5 splits every input
# edge, so many input vertices have only inserted neighbours: their 3D directions come from the
# signposts): transport still returns the source's vector everywhere and the boundary-aligned
# cross field is the constant cross
def test_transport_and_field_flat_l_refined(cli):
    o = cli.out
    mesh = o / "flat_l_r.obj"
    nv = write_flat_l(mesh)
    vec = (0.6, -0.8, 0.5)
    t = o / "flat_l_r_t.txt"
    r = cli.ok("transport", mesh, "--source", nv // 3, "--vector", ",".join(map(str, vec)),
               "--refine", "--resolution", 0.5, "-o", t)
    assert grep("circumcenters", r.err), r.describe()  # refined
    got = vectors(t)
    assert len(got) == nv
    for k, v in enumerate(got):
        assert max(abs(v[0] - vec[0]), abs(v[1] - vec[1]), abs(v[2])) <= 1e-7, (k, v)
    f = o / "flat_l_r_f.txt"
    r = cli.ok("field", mesh, "--symmetry", 4, "--align-boundary", "--refine", "--resolution",
               0.5, "-o", f, "--quiet")
    assert grep("total index 0/4", r.out), r.describe()
    got = vectors(f)
    assert len(got) == nv
    for k, v in enumerate(got):
        a = 4 * math.atan2(v[1], v[0])
        assert abs(math.cos(a) - 1) + abs(math.sin(a)) <= 1e-7, (k, v)


def check_tangent(mesh, path, tol):
    """Every vector tangent against the faces' area-weighted normal at its vertex, where those
    normals do not cancel (|Σ n_f| ≥ ½ Σ |n_f|): |v·n| ≤ tol·|v|, and at least 90% checked."""
    p = obj_vertices(mesh)
    normal = [[0.0, 0.0, 0.0] for _ in p]
    total = [0.0] * len(p)
    for face in obj_faces(mesh):
        i, j, k = (x - 1 for x in face[:3])
        u = [p[j][c] - p[i][c] for c in range(3)]
        w = [p[k][c] - p[i][c] for c in range(3)]
        cross = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        length = norm(cross)
        for x in (i, j, k):
            for c in range(3):
                normal[x][c] += cross[c]
            total[x] += length
    rows = vectors(path)
    checked = 0
    for r, v in enumerate(rows):
        nn, vn = norm(normal[r]), norm(v)
        if nn < 0.5 * total[r] or vn == 0:
            continue
        checked += 1
        d = sum(v[c] * normal[r][c] for c in range(3)) / nn
        assert abs(d) <= tol * vn, f"not tangent at {r + 1}: {d / vn}"
    assert checked >= 0.9 * len(rows), (checked, len(rows))


def check_on_unit_sphere(points, path):
    """Tangent to the unit sphere at the points: |v·x| ≤ 0.05·|v| (normals by PCA)."""
    for k, (x, v) in enumerate(zip(vectors(points), vectors(path))):
        vn = norm(v)
        d = sum(x[c] * v[c] for c in range(3))
        assert vn != 0 and abs(d) <= 0.05 * vn, f"not tangent at {k + 1}: {d / vn if vn else 0}"


def check_lengths(path, length):
    for v in vectors(path):
        assert length - 1e-6 <= norm(v) <= length + 1e-6, (v, length)


def run_frame_path(cli, source, mesh, rows, tol, *options):
    """field, transport and logmap on `source`: one row per input vertex, no NaN, field vectors
    of unit length, transported ones of one length, tangent (when `mesh` is given), the log
    map 0 at its source."""
    o = cli.out
    f, t, lm = o / "fp_f.txt", o / "fp_t.txt", o / "fp_l.txt"
    r = cli.ok("field", source, "--symmetry", 4, "-o", f, "--quiet", *options)
    assert grep("4-direction field", r.out), r.describe()
    r = cli.ok("transport", source, "--source", 0, "--vector", "0,0,1", "-o", t, "--quiet",
               *options)
    assert grep(f"{rows} tangent vectors, 0 unreached", r.out), r.describe()
    r = cli.ok("logmap", source, "--source", 0, "-o", lm, "--quiet", *options)
    assert grep("log map about vertex 0", r.out), r.describe()
    for path in (f, t, lm):
        assert count_lines(path) == rows
        assert "nan" not in path.read_text().lower(), path
    check_lengths(f, 1)
    check_lengths(t, norm(vectors(t)[0]))
    if mesh is not None:
        check_tangent(mesh, f, tol)
        check_tangent(mesh, t, tol)
    first = vectors(lm)[0]
    assert first[0] == 0 and first[1] == 0, first


# field, transport and logmap on the frame path (docs/decisions.md, "Tangent fields on point
# clouds and tufted covers"): a point cloud (spot's vertices), a nonmanifold mesh
# (triple_vierbein: 20 edges with 3 faces) and spot forced onto the tufted cover. One row per
# input vertex; field vectors of unit length; transported vectors of one length (one source);
# all tangent: |v·n| against the faces' area-weighted normals (where they do not cancel) below
# 1e-6·|v| on meshes; on a unit-sphere point cloud (1,500 Fibonacci points, normals by PCA)
# against the exact normal, below 0.05·|v|.
def test_fields_frame_path(cli):
    o = cli.out
    sphere = o / "fp_sphere.xyz"
    n, g = 1500, 3.14159265358979 * (3 - math.sqrt(5))
    with open(sphere, "w") as f:
        for i in range(n):
            z = 1 - (2 * i + 1) / n
            r = math.sqrt(1 - z * z)
            f.write(f"{r * math.cos(g * i):.17g} {r * math.sin(g * i):.17g} {z:.17g}\n")
    run_frame_path(cli, cli.spot_points("fp_spot.xyz"), None, SPOT_VERTICES, 0)
    run_frame_path(cli, sphere, None, 1500, 0)
    check_on_unit_sphere(sphere, o / "fp_f.txt")
    check_on_unit_sphere(sphere, o / "fp_t.txt")
    vierbein = cli.data / "triple_vierbein.obj"
    run_frame_path(cli, vierbein, vierbein, 75, 1e-6)
    run_frame_path(cli, cli.spot, cli.spot, SPOT_VERTICES, 1e-6, "--tufted")
    # Poincaré–Hopf through the input's faces on the tufted path: 2 for vectors, 8/4 for crosses
    r = cli.ok("field", cli.spot, "--tufted", "-o", o / "fp_f.ply", "--quiet")
    assert grep("total index 2/1", r.out), r.describe()
    r = cli.ok("field", cli.spot, "--tufted", "--symmetry", 4, "-o", o / "fp_f.ply", "--quiet")
    assert grep("total index 8/4", r.out), r.describe()


def soup_pieces(path):
    """The pieces of an OBJ counted from its faces alone (union-find): the piece of each vertex
    (0-based) and the set of pieces without area."""
    verts, faces = obj_vertices(path), [tuple(i - 1 for i in f) for f in obj_faces(path)]
    piece = face_components(len(verts), faces)
    area = {p: 0.0 for p in piece}
    for a, b, c in faces:
        u = [verts[b][k] - verts[a][k] for k in range(3)]
        w = [verts[c][k] - verts[a][k] for k in range(3)]
        area[piece[a]] += norm((u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                u[0] * w[1] - u[1] * w[0])) / 2
    return piece, {p for p, a in area.items() if a == 0}


# A triangle soup (tests/data/soup_icosphere.obj: 8 pieces of an icosphere with their own,
# coincident vertices, a lone flat triangle, a zero-area face), on the manifold and the tufted
# path and as a point cloud: `field` works for n = 1, 2, 4 (before, the shift of one component
# made the factorization fail for all), reports the components as counted here, gives unit
# vectors on every piece with area and 0 0 0 on the zero-area one; with --align-boundary the 9
# disks carry index n each; `transport` is finite on the source's piece, nan elsewhere, counted.
def test_soup(cli):
    o, soup = cli.out, cli.data / "soup_icosphere.obj"
    piece, flat = soup_pieces(soup)
    pieces = len(set(piece))
    assert (pieces, len(flat)) == (10, 1)
    for path in ([], ["--tufted"], ["--pointcloud"]):
        for n in (1, 2, 4):
            r = cli.ok("field", soup, "--symmetry", n, "-o", o / "soup_f.txt", *path)
            if not path or path == ["--tufted"]:
                assert grep(f"{pieces} components: {pieces - len(flat)} with their own smoothest "
                            f"field, 0 held by constraints, {len(flat)} without a field "
                            f"\\({len(flat)} flat", r.err), r.describe()
            rows = vectors(o / "soup_f.txt")
            assert len(rows) == len(piece)
            for v, row in enumerate(rows):
                no_field = piece[v] in flat and path != ["--pointcloud"]
                assert abs(norm(row) - (0 if no_field else 1)) <= 1e-9, (path, n, v, row)
    # vectors along the boundary: index χ = 1 per disk (the bisector at corners); crosses and
    # line fields leave indices at corners they do not fit (Poincaré–Hopf with boundary, checked
    # in soup_fields_test.cpp)
    for path in ([], ["--tufted"]):
        r = cli.ok("field", soup, "--symmetry", 1, "--align-boundary", "-o", o / "soup_a.txt",
                   "--quiet", *path)
        assert grep("total index 9/1", r.out), r.describe()
    (o / "soup_c.txt").write_text("243 1 0 0\n240 0 1 0\n")
    r = cli.ok("field", soup, "--constraints", o / "soup_c.txt", "-o", o / "soup_c.ply")
    assert grep("1 directions on them skipped", r.err), r.describe()
    for path in ([], ["--tufted"]):
        for source in (0, 240):
            t = o / "soup_t.txt"
            r = cli.ok("transport", soup, "--source", source, "--vector", "1,0,0", "-o", t,
                       "--quiet", *path)
            reached = [v for v in range(len(piece)) if piece[v] == piece[source]]
            assert grep(f"{len(piece) - len(reached)} unreached vertices \\(nan\\)", r.out), \
                r.describe()
            rows = vectors(t)
            for v, row in enumerate(rows):
                if piece[v] == piece[source]:
                    assert all(math.isfinite(x) for x in row), (v, row)
                    assert abs(norm(row) - norm(rows[source])) <= 1e-9, (v, row)
                else:
                    assert all(math.isnan(x) for x in row), (v, row)


def grid_obj(path, n, copies=1, extra=0):
    """A flat n×n grid on the unit square (copies side by side, 2 apart in x), plus `extra`
    unreferenced vertices at the end."""
    vertices, faces = [], []
    for c in range(copies):
        base = len(vertices)
        vertices += [(2.0 * c + i / n, j / n, 0.0) for j in range(n + 1) for i in range(n + 1)]
        for j in range(n):
            for i in range(n):
                a = base + j * (n + 1) + i
                faces += [(a, a + 1, a + n + 2), (a, a + n + 2, a + n + 1)]
    vertices += [(-5.0 - k, 0.0, 0.0) for k in range(extra)]
    write_obj(path, vertices, [tuple(x + 1 for x in f) for f in faces])
    return vertices


def ply_vertex_table(path):
    """The vertex element of a .ply written by ifem (ascii or binary little endian) as a dict
    property -> list of values."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    fmt = header[1].split()[1]
    names, types, count, in_vertex = [], [], 0, False
    for line in header:
        w = line.split()
        if w[0] == "element":
            in_vertex = w[1] == "vertex"
            if in_vertex:
                count = int(w[2])
        elif w[0] == "property" and in_vertex:
            types.append({"float": "f", "double": "d", "float32": "f", "float64": "d"}[w[1]])
            names.append(w[2])
    if fmt == "ascii":
        rows = [list(map(float, line.split()))
                for line in data[end:].decode().splitlines()[:count]]
    else:
        row = struct.Struct("<" + "".join(types))
        rows = [row.unpack_from(data, end + k * row.size) for k in range(count)]
    return {name: [r[k] for r in rows] for k, name in enumerate(names)}


# logmap --method: affine is the plane's identity map up to one rotation on a flat grid (the
# vector heat method is not: its radius is a heat distance); a second copy and unreferenced
# vertices are 'nan nan' in the .txt and distance inf in the .ply, counted; a bad method is a
# usage error; --help teaches both
def test_logmap_methods_and_unreached(cli):
    o = cli.out
    n = 12
    grid = o / "two_grids.obj"
    p = grid_obj(grid, n, copies=2, extra=2)
    per = (n + 1) ** 2
    src = 6 * (n + 1) + 6
    for method in ("affine", "vector-heat", "blend"):
        txt = o / f"lm_{method}.txt"
        r = cli.ok("logmap", grid, "--source", src, "--method", method, "-o", txt, "--quiet")
        assert grep(f"{per + 2} unreached vertices", r.out), r.describe()
        uv = vectors(txt)
        assert len(uv) == 2 * per + 2
        assert all(math.isnan(u) and math.isnan(v) for u, v in uv[per:]), uv[per:per + 3]
        assert all(math.isfinite(u) and math.isfinite(v) for u, v in uv[:per])
        assert uv[src] == (0.0, 0.0)
        assert all(math.hypot(u, v) > 0 for k, (u, v) in enumerate(uv[:per]) if k != src)
        ply = o / f"lm_{method}.ply"
        cli.ok("logmap", grid, "--source", src, "--method", method, "-o", ply, "--quiet")
        t = ply_vertex_table(ply)
        assert all(math.isinf(d) for d in t["distance"][per:]), t["distance"][per:per + 3]
        assert all(math.isnan(u) for u in t["u"][per:])
        assert all(math.isfinite(d) for d in t["distance"][:per])
    uv = vectors(o / "lm_affine.txt")
    rot = [0.0, 0.0]
    for k in range(per):
        if k == src:
            continue
        ex = complex(p[k][0] - p[src][0], p[k][1] - p[src][1])
        z = complex(*uv[k]) / ex
        rot[0] += z.real / abs(z)
        rot[1] += z.imag / abs(z)
    turn = complex(*rot) / abs(complex(*rot))
    for k in range(per):
        ex = complex(p[k][0] - p[src][0], p[k][1] - p[src][1])
        assert abs(complex(*uv[k]) / turn - ex) <= 1e-6, (k, uv[k], ex)
    vh = vectors(o / "lm_vector-heat.txt")
    assert max(abs(abs(complex(*vh[k])) - abs(complex(*uv[k]))) for k in range(per)) > 1e-3
    r = cli.run("logmap", grid, "--source", src, "--method", "exact", "-o", o / "bad.txt")
    assert r.rc == 2, r.describe()
    assert grep("--method 'exact': expected 'blend', 'affine' or 'vector-heat'", r.err), r.describe()
    assert not (o / "bad.txt").exists()
    r = cli.ok("logmap", "--help")
    assert grep("--method", r.out) and grep("affine", r.out) and grep("local charts", r.out)


# a range scan with boundary ears takes the tufted path: every vertex `ifem distance` reaches
# (finite) is nonzero in the log map except the source, every other one nan; the counts agree
def test_logmap_scan_has_no_silent_zeros(cli, shared_data):
    mesh = shared_data / "meshes" / "stanford_bunny_scan.obj"
    o = cli.out
    for src in (2000,):  # vertices 1884 and 21207 were (0, 0) from here
        cli.ok("distance", mesh, "--source", src, "-o", o / "d.txt", "--quiet")
        dist = [float(x) for x in lines(o / "d.txt")]
        unreachable = sum(1 for d in dist if math.isinf(d))
        for method in ("affine", "vector-heat", "blend"):
            r = cli.ok("logmap", mesh, "--source", src, "--method", method, "-o", o / "l.txt",
                       "--quiet")
            assert grep(f" {unreachable} unreached vertices", r.out), r.describe()
            assert not grep("unresolved", r.out), r.describe()
            uv = vectors(o / "l.txt")
            for k, (d, (u, v)) in enumerate(zip(dist, uv)):
                if math.isinf(d):
                    assert math.isnan(u) and math.isnan(v), (method, k)
                elif k != src:
                    assert math.hypot(u, v) > 0, (method, src, k, d)


# a strip 1500 edges long: the heat underflows beyond ~700 edges from the source; those vertices
# are nan and counted as unresolved (not unreached, not 0); before that the affine map is exact
def test_logmap_underflow_is_reported(cli):
    n = 1500
    strip = cli.out / "strip.obj"
    write_obj(strip, [(i, j, 0.0) for j in range(3) for i in range(n + 1)],
              [f for j in range(2) for i in range(n)
               for a in [j * (n + 1) + i + 1] for f in ((a, a + 1, a + n + 2),
                                                        (a, a + n + 2, a + n + 1))])
    for method in ("affine", "vector-heat", "blend"):
        out = cli.out / f"strip_{method}.txt"
        r = cli.ok("logmap", strip, "--source", 0, "--method", method, "-o", out, "--quiet")
        m = re.search(r"0 unreached vertices \(nan\), (\d+) unresolved", r.out)
        assert m, r.describe()
        uv = vectors(out)
        bad = [k for k, (u, v) in enumerate(uv) if math.isnan(u) or math.isnan(v)]
        assert len(bad) == int(m.group(1)) and 0 < len(bad) < 0.6 * len(uv), r.describe()
        assert all(k % (n + 1) > 600 for k in bad)
        if method == "affine":
            for k, (u, v) in enumerate(uv):
                x, y = k % (n + 1), k // (n + 1)
                if k % (n + 1) < 600 and k > 0:
                    assert abs(math.hypot(u, v) - math.hypot(x, y)) <= 1e-9 * math.hypot(x, y), \
                        (k, u, v)
