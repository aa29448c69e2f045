"""refine / RefinedTriangulation / load_refined: against `ifem refine`'s files on spot (common
subdivision, --mesh, --save; with default and other options, 1e-12), the invariants of a
refinement (angles, area, the IDT Laplacian, input vertices in place), save → load bit for bit,
data transfer exact for linear functions on a flat mesh, and bad inputs."""

import numpy as np
import pytest
import scipy.sparse

import conftest
import ifem
from conftest import run_cli, test_data

# (Python keyword arguments, the same as `ifem refine` options)
OPTIONS = {
    "default": ({}, []),
    "min_angle_28": ({"min_angle": 28}, ["--min-angle", 28]),
    "resolution": ({"resolution": 0.7, "min_angle": 20}, ["--resolution", 0.7, "--min-angle", 20]),
    "relax": ({"relax": 2, "max_edge": 0.05}, ["--relax", 2, "--max-edge", 0.05]),
    "capped": ({"max_area": 2e-4, "max_insertions": 3000, "mollify": 1e-3},
               ["--max-area", 2e-4, "--max-insertions", 3000, "--mollify", 1e-3]),
}


@pytest.fixture(scope="module")
def spot():
    return ifem.read_mesh(test_data("spot.obj"))


@pytest.fixture(scope="module")
def refined(spot):
    """spot refined with each option set, computed once."""
    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = ifem.refine(*spot, **OPTIONS[name][0])
        return cache[name]
    return get


def read_ascii_ply(path):
    """(V, F, {face property: values}) of an ASCII PLY with a vertex and a face element."""
    lines = path.read_text().splitlines()
    end = lines.index("end_header")
    header = [line.split() for line in lines[:end]]
    n_v = next(int(h[2]) for h in header if h[:2] == ["element", "vertex"])
    n_f = next(int(h[2]) for h in header if h[:2] == ["element", "face"])
    face_at = next(i for i, h in enumerate(header) if h[:2] == ["element", "face"])
    props = [h[2] for h in header[face_at + 1:] if h[0] == "property" and h[1] != "list"]
    V = np.array([[float(x) for x in line.split()[:3]] for line in lines[end + 1:end + 1 + n_v]])
    rows = np.array([[int(x) for x in line.split()]
                     for line in lines[end + 1 + n_v:end + 1 + n_v + n_f]])
    assert (rows[:, 0] == 3).all()
    return V, rows[:, 1:4], {p: rows[:, 4 + i] for i, p in enumerate(props)}


def corner_angles(lengths):
    """#F×3 corner angles (degrees) from #F×3 side lengths l[f, k] (side F[f,k] → F[f,k+1]):
    the angle at corner k is opposite side k + 1."""
    a, b, c = lengths[:, 0], lengths[:, 1], lengths[:, 2]
    opposite = np.stack([b, c, a], axis=1)
    s1 = np.stack([c, a, b], axis=1)  # the two sides at each corner
    s2 = np.stack([a, b, c], axis=1)
    cos = (s1**2 + s2**2 - opposite**2) / (2 * s1 * s2)
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


def mesh_area(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]),
                                axis=1).sum()


def flat_grid(n=8, seed=5):
    """A flat jittered grid of the unit square, n×n vertices, in the plane z = 0."""
    return conftest.flat_grid(n - 1, jitter=0.35, seed=seed)


# ---- against the CLI ------------------------------------------------------------------------

@pytest.mark.parametrize("name", list(OPTIONS))
def test_matches_cli(tmp_path, spot, refined, name):
    V, F = spot
    r = refined(name)
    cs, mesh = tmp_path / "cs.ply", tmp_path / "mesh.ply"
    out = run_cli("refine", test_data("spot.obj"), *OPTIONS[name][1], "-o", cs, "--mesh", mesh,
                  "--ascii", "--quiet")
    assert f"{r.n_input_vertices} input -> {r.report['vertices_after']} refined" in out
    # the common subdivision, with its face properties
    Vc, Fc, props = read_ascii_ply(cs)
    Vs, Fs, intrinsic_face, input_face = r.common_subdivision()
    scale = abs(V).max()
    assert Vs.shape == Vc.shape and abs(Vs - Vc).max() <= 1e-12 * scale
    assert np.array_equal(Fs, Fc)
    assert np.array_equal(intrinsic_face, props["intrinsic_face"])
    assert np.array_equal(input_face, props["input_face"])
    # --mesh: every intrinsic vertex's position on the input, and the refined faces
    Vm, Fm, info = ifem.read_mesh(mesh, return_info=True)
    P = r.positions()
    assert P.shape == Vm.shape == (r.n_vertices, 3) and abs(P - Vm).max() <= 1e-12 * scale
    assert np.array_equal(r.faces(), Fm) and r.faces().shape == (r.n_faces, 3)
    inserted = info["vertex_properties"]["inserted"]
    assert np.array_equal(inserted, np.arange(r.n_vertices) >= r.n_input_vertices)


def test_cli_save_loads_in_python(tmp_path, spot, refined):
    r = refined("default")
    run_cli("refine", test_data("spot.obj"), "--save", tmp_path / "spot.ifem", "--quiet")
    loaded = ifem.load_refined(tmp_path / "spot.ifem")
    assert np.array_equal(loaded.positions(), r.positions())
    assert np.array_equal(loaded.faces(), r.faces())
    assert np.array_equal(loaded.edge_lengths(), r.edge_lengths())


# ---- invariants -----------------------------------------------------------------------------

def assert_idt_laplacian(L, M, n):
    assert isinstance(L, scipy.sparse.csc_matrix) and L.shape == (n, n) and M.shape == (n, n)
    scale = abs(L.diagonal()).max()
    assert abs(L - L.T).max() <= 1e-14 * scale                    # symmetric
    assert abs(L @ np.ones(n)).max() <= 1e-12 * scale              # constants in the kernel
    off = L - scipy.sparse.diags(L.diagonal())
    assert off.max() <= 1e-10 * scale                              # IDT: weights ≥ 0
    assert (M.diagonal() > 0).all()                                # every vertex has area


@pytest.mark.parametrize("name", ["default", "min_angle_28"])
def test_refinement_invariants(spot, refined, name):
    V, F = spot
    r = refined(name)
    rep = r.report
    min_angle = OPTIONS[name][0].get("min_angle", 25)
    n, n_in = r.n_vertices, r.n_input_vertices
    assert n_in == len(V) and n == rep["vertices_after"] > n_in
    assert rep["insertions"] == n - n_in and rep["vertices_before"] == n_in
    assert rep["min_angle_before"] < min_angle <= rep["min_angle_after_excluding_needles"]
    assert rep["relax"] is None and "refined:" in rep["summary"]
    # the input's vertices are where they were, inserted vertices on the surface
    P = r.positions()
    assert np.array_equal(P[:n_in], V)
    # every angle at least the bound, unless the report says why not
    angles = corner_angles(r.edge_lengths())
    assert abs(angles.sum(axis=1) - 180).max() < 1e-9
    if not rep["hit_insertion_cap"] and rep["needle_faces"] == 0:
        assert angles.min() >= min_angle - 1e-9
        assert abs(angles.min() - rep["min_angle_after"]) < 1e-9
    else:
        assert (angles.min(axis=1) >= min_angle - 1e-9).sum() >= r.n_faces - rep["needle_faces"] \
            - rep["bad_faces_left"]
    # every vertex in some face, and the refined mesh has the input's Euler characteristic
    Fr = r.faces()
    assert np.array_equal(np.unique(Fr), np.arange(n))
    edges = np.unique(np.sort(np.r_[Fr[:, [0, 1]], Fr[:, [1, 2]], Fr[:, [2, 0]]], axis=1), axis=0)
    assert n - len(edges) + len(Fr) == 2  # spot is a sphere
    # same surface: the total area is the input's (the operators of the unrefined mesh agree)
    L, M = r.laplacian()
    assert_idt_laplacian(L, M, n)
    _, M0 = ifem.laplacian(V, F)
    assert abs(M.sum() - M0.sum()) <= 1e-10 * M0.sum()
    if rep["mollify_delta"] == 0:
        assert abs(M.sum() - mesh_area(V, F)) <= 1e-10 * M0.sum()
    Vs, Fs, intrinsic_face, input_face = r.common_subdivision()
    assert abs(mesh_area(Vs, Fs) - M0.sum()) <= 1e-10 * M0.sum()
    assert np.array_equal(Vs[:n_in], V)
    assert intrinsic_face.max() < r.n_faces and input_face.max() < len(F)
    assert np.array_equal(np.unique(input_face), np.arange(len(F)))
    assert repr(r).startswith(f"RefinedTriangulation(n_input_vertices={n_in}, n_vertices={n}")


def test_resolution_makes_edges_short(refined):
    r = refined("resolution")
    rep = r.report
    ell = rep["target_edge_length"]
    assert abs(ell - 0.7 * rep["input_mean_edge_length"]) <= 1e-15 * ell
    # no triangle above the equilateral area of side ℓ (unless stopped)
    l = r.edge_lengths()
    s = l.sum(axis=1) / 2
    area = np.sqrt(np.maximum(s * (s - l[:, 0]) * (s - l[:, 1]) * (s - l[:, 2]), 0))
    assert not rep["hit_insertion_cap"]
    assert area.max() <= np.sqrt(3) / 4 * ell**2 * (1 + 1e-9)


def test_insertion_cap(spot):
    r = ifem.refine(*spot, max_insertions=10)
    rep = r.report
    assert rep["hit_insertion_cap"] and rep["insertions"] == 10
    assert r.n_vertices == len(spot[0]) + 10
    assert rep["bad_faces_left"] > 0
    assert "stopped at the insertion cap" in repr(r)
    L, M = r.laplacian()
    assert_idt_laplacian(L, M, r.n_vertices)


def test_threads_give_the_same_results(spot, refined):
    # the GIL is released while refining and tracing: concurrent calls must not interfere
    from concurrent.futures import ThreadPoolExecutor

    def work(name):
        r = ifem.refine(*spot, **OPTIONS[name][0])
        return r.positions(), r.common_subdivision()[0]
    names = ["default", "min_angle_28"] * 2
    with ThreadPoolExecutor(max_workers=4) as pool:
        results = list(pool.map(work, names))
    for name, (P, Vs) in zip(names, results):
        assert np.array_equal(P, refined(name).positions())
        assert np.array_equal(Vs, refined(name).common_subdivision()[0])


# ---- save / load ----------------------------------------------------------------------------

def test_save_load_round_trip(tmp_path, refined):
    r = refined("min_angle_28")
    r.save(tmp_path / "r.ifem")
    s = ifem.load_refined(str(tmp_path / "r.ifem"))
    assert s.report is None
    assert (s.n_input_vertices, s.n_vertices, s.n_faces) == \
        (r.n_input_vertices, r.n_vertices, r.n_faces)
    for get in ("positions", "faces", "edge_lengths"):
        assert np.array_equal(getattr(s, get)(), getattr(r, get)()), get
    for a, b in zip(s.common_subdivision(), r.common_subdivision()):
        assert np.array_equal(a, b)
    (Ls, Ms), (Lr, Mr) = s.laplacian(), r.laplacian()
    assert (Ls != Lr).nnz == 0 and (Ms != Mr).nnz == 0
    f = np.sin(np.arange(r.n_input_vertices))
    assert np.array_equal(s.from_input(f), r.from_input(f))
    assert repr(s) == (f"RefinedTriangulation(n_input_vertices={r.n_input_vertices}, "
                       f"n_vertices={r.n_vertices}, n_faces={r.n_faces})")


# ---- data transfer --------------------------------------------------------------------------

def test_from_input_is_exact_for_linear_functions_on_a_flat_mesh():
    V, F = flat_grid()
    r = ifem.refine(V, F, min_angle=30, resolution=0.5)
    assert r.n_vertices > 2 * len(V)
    P = r.positions()
    assert abs(P[:, 2]).max() == 0 and P[:, :2].min() >= 0 and P[:, :2].max() <= 1
    u = lambda X: 2.0 * X[:, 0] - 3.0 * X[:, 1] + 0.5  # noqa: E731
    w = lambda X: X[:, 0] + 7.0 * X[:, 1]  # noqa: E731
    carried = r.from_input(u(V))
    assert carried.shape == (r.n_vertices,) and abs(carried - u(P)).max() < 1e-12
    both = r.from_input(np.c_[u(V), w(V)])
    assert both.shape == (r.n_vertices, 2) and abs(both - np.c_[u(P), w(P)]).max() < 1e-12
    assert np.array_equal(r.to_input(carried), u(V))
    assert np.array_equal(r.to_input(both), np.c_[u(V), w(V)])
    # P1 elements reproduce linear functions: L u = 0 away from the boundary; area is 1
    L, M = r.laplacian()
    assert_idt_laplacian(L, M, r.n_vertices)
    interior = (P[:, :2].min(axis=1) > 1e-12) & (P[:, :2].max(axis=1) < 1 - 1e-12)
    assert abs((L @ u(P))[interior]).max() < 1e-11
    assert abs(M.sum() - 1.0) < 1e-12
    # the relaxed refinement keeps all of that
    relaxed = ifem.refine(V, F, min_angle=25, resolution=0.5, relax=2)
    assert relaxed.report["relax"]["passes"] == 2
    assert abs(relaxed.from_input(u(V)) - u(relaxed.positions())).max() < 1e-12


# ---- bad inputs -----------------------------------------------------------------------------

def nonmanifold_mesh():
    """Three flaps on one edge plus a square: an edge with three faces."""
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0.2], [0.5, 0.1, 1], [1.5, 1, 0]])
    return V, np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 5, 2]])


def moebius_strip(n=12):
    t = 2 * np.pi * np.arange(n) / n
    V = []
    for s in (-1, 1):
        V += [[(2 + 0.5 * s * np.cos(a / 2)) * np.cos(a), (2 + 0.5 * s * np.cos(a / 2)) * np.sin(a),
               0.5 * s * np.sin(a / 2)] for a in t]
    F = []
    for i in range(n):
        j = (i + 1) % n
        a, b = i, n + i
        c, d = (j, n + j) if j else (n + j, j)  # the half twist glues the rails crosswise
        F += [[a, b, d], [a, d, c]]
    return np.array(V), np.array(F)


@pytest.mark.parametrize("kwargs, match", [
    ({"min_angle": 0}, "min_angle"), ({"min_angle": 40}, "min_angle"),
    ({"min_angle": float("nan")}, "min_angle"), ({"resolution": -1}, "resolution"),
    ({"resolution": float("inf")}, "resolution"), ({"max_area": -0.1}, "max_area"),
    ({"max_insertions": -1}, "max_insertions"), ({"max_insertions": 2.5}, "max_insertions"),
    ({"relax": -1}, "relax"), ({"max_edge": 0.1}, "relax"),
    ({"max_edge": -1, "relax": 1}, "max_edge"),
    ({"mollify": -1}, "mollify"), ({"memory_budget": 0}, "memory_budget"),
    ({"memory_budget": 1e-9}, "budget"),
])
def test_bad_options(kwargs, match):
    V, F = flat_grid(4)
    with pytest.raises(ifem.InvalidInput, match=match):
        ifem.refine(V, F, **kwargs)


def test_bad_arrays_and_meshes():
    V, F = flat_grid(4)
    Vn = V.copy()
    Vn[5, 1] = np.nan
    with pytest.raises(ifem.InvalidInput, match="V row 5"):
        ifem.refine(Vn, F)
    with pytest.raises(ifem.InvalidInput, match="F row 0"):
        ifem.refine(V, F + 100)
    with pytest.raises(ifem.InvalidInput, match="no faces"):
        ifem.refine(V, np.zeros((0, 3), int))
    with pytest.raises(ifem.NonManifoldInput, match="signposts"):
        ifem.refine(*nonmanifold_mesh())
    with pytest.raises(ifem.NonOrientableInput, match="signposts"):
        ifem.refine(*moebius_strip())
    r = ifem.refine(V, F)
    with pytest.raises(ifem.InvalidInput, match="one row per vertex"):
        r.to_input(np.zeros(r.n_vertices + 1))
    with pytest.raises(ifem.InvalidInput, match="x must have 16 values"):
        r.from_input(np.zeros(15))
    with pytest.raises(ifem.InvalidInput, match="one row per input vertex"):
        r.from_input(np.zeros((15, 2)))
    with pytest.raises(ifem.InvalidInput, match="not finite"):
        r.from_input(np.full(16, np.inf))


def test_bad_files(tmp_path):
    with pytest.raises(ifem.IoError) as e:
        ifem.load_refined(tmp_path / "missing.ifem")
    assert isinstance(e.value, OSError) and "missing.ifem" in str(e.value)
    bad = tmp_path / "bad.ifem"
    bad.write_text("ifem-signpost 1\nmollify 1e-5\ninput_vertices 3\n0 0 0\n1 0\n")
    with pytest.raises(ifem.IoError, match="line"):
        ifem.load_refined(bad)
    bad.write_text("ply\nformat ascii 1.0\n")
    with pytest.raises(OSError, match="ifem-signpost"):
        ifem.load_refined(bad)
    V, F = flat_grid(4)
    with pytest.raises(ifem.IoError):
        ifem.refine(V, F).save(tmp_path / "no" / "such" / "dir" / "r.ifem")
