"""HeatDistanceSolver / heat_distance / eigen / poisson: against the CLI's outputs (same inputs,
1e-12 relative) on a manifold mesh, a nonmanifold mesh and a point cloud, with and without
--refine; analytic answers (flat distances, sphere eigenvalues, linear Poisson solutions);
surface points; argument checking; the GIL released during the work."""

import threading
import time

import numpy as np
import pytest

import ifem
from conftest import flat_grid, read_txt, run_cli, test_data

# --- inputs -------------------------------------------------------------------------------------


def spot():
    return test_data("spot.obj")


def nonmanifold(tmp_path):
    """spot with one extra triangle on an existing edge: that edge has three faces, so the
    whole mesh takes the tufted path."""
    V, F = ifem.read_mesh(spot())
    a, b = F[0, 0], F[0, 1]
    tip = (V[a] + V[b]) / 2 + 0.05 * np.cross(V[b] - V[a], [0.0, 0.0, 1.0])
    p = tmp_path / "spot_flap.obj"
    with open(p, "w") as out:
        for v in np.vstack([V, tip]):
            out.write("v %.17g %.17g %.17g\n" % tuple(v))
        for f in np.vstack([F, [a, b, len(V)]]) + 1:
            out.write("f %d %d %d\n" % tuple(f))
    return p


def point_cloud(tmp_path):
    V, _ = ifem.read_mesh(spot())
    p = tmp_path / "cloud.xyz"
    np.savetxt(p, V[::2], fmt="%.17g")
    return p


def grid(n, jitter=0.3):
    """conftest's flat unit square with n vertices a side, and the mask of its interior."""
    V, F = flat_grid(n - 1, jitter=jitter)
    x, y = V[:, 0], V[:, 1]
    return V, F, (x > 0) & (x < 1) & (y > 0) & (y < 1)


def face_near(V, F, x, y):
    """The face whose centroid is nearest (x, y)."""
    return int(np.argmin(np.linalg.norm(V[F].mean(1)[:, :2] - [x, y], axis=1)))


def icosphere(level):
    """The unit sphere: an icosahedron subdivided `level` times, projected onto the sphere."""
    t = (1 + 5 ** 0.5) / 2
    V = [np.array(v, float) / np.linalg.norm(v) for v in
         [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
          (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        mid = {}

        def m(a, b):
            if (min(a, b), max(a, b)) not in mid:
                p = V[a] + V[b]
                V.append(p / np.linalg.norm(p))
                mid[min(a, b), max(a, b)] = len(V) - 1
            return mid[min(a, b), max(a, b)]

        F = [g for a, b, c in F for g in
             ((a, m(a, b), m(c, a)), (b, m(b, c), m(a, b)), (c, m(c, a), m(b, c)),
              (m(a, b), m(b, c), m(c, a)))]
    return np.array(V), np.array(F)


def inputs(kind, tmp_path):
    """(file, V, F, extra CLI arguments) of a test input."""
    path = {"spot": spot, "nonmanifold": lambda: nonmanifold(tmp_path),
            "pointcloud": lambda: point_cloud(tmp_path)}[kind]()
    V, F = ifem.read_mesh(path)
    return path, V, F, (["--knn", 12] if kind == "pointcloud" else [])


def assert_close(a, b, rtol=1e-12):
    """Same infinities, finite values within rtol × the largest finite magnitude."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    assert (np.isinf(a) == np.isinf(b)).all()
    finite = np.isfinite(b)
    assert abs(a[finite] - b[finite]).max() <= rtol * abs(b[finite]).max()


# --- against the CLI ----------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["spot", "nonmanifold", "pointcloud"])
@pytest.mark.parametrize("refine", [False, True])
def test_distance_matches_cli(tmp_path, kind, refine):
    path, V, F, extra = inputs(kind, tmp_path)
    knn = {"knn": 12} if kind == "pointcloud" else {}
    sources = [0, 57, 1000]
    if refine and kind == "pointcloud":  # the CLI refuses it too
        with pytest.raises(ifem.InvalidInput, match="point clouds"):
            ifem.heat_distance(V, F, sources, refine=True, **knn)
        return
    args = ["--refine"] if refine else []
    run_cli("distance", path, "--source", "0,57,1000", "-o", tmp_path / "d.txt", "--quiet",
            *args, *extra)
    expected = read_txt(tmp_path / "d.txt")
    d = ifem.heat_distance(V, F, sources, refine=refine, **knn)
    assert d.dtype == np.float64 and d.shape == (len(V),)
    assert_close(d, expected)
    assert (d[sources] == 0).all()
    solver = ifem.HeatDistanceSolver(V, F, refine=refine, **knn)
    assert_close(solver.compute_distance(np.array(sources, np.uint16)), expected)
    assert solver.info["refined"] == refine
    assert solver.info["path"] == {"spot": "manifold", "nonmanifold": "tufted",
                                   "pointcloud": "pointcloud"}[kind]


def test_distance_options_match_cli(tmp_path):
    V, F = ifem.read_mesh(spot())
    run_cli("distance", spot(), "--source", "12", "-o", tmp_path / "d.txt", "--quiet",
            "--time-factor", 3, "--correction-steps", 2, "--refine", "--resolution", 0.7,
            "--min-angle", 20, "--max-insertions", 4000)
    d = ifem.heat_distance(V, F, 12, time_factor=3, correction_steps=2, refine=True,
                           resolution=0.7, min_angle=20, max_insertions=4000)
    assert_close(d, read_txt(tmp_path / "d.txt"))
    run_cli("distance", spot(), "--source", "12", "-o", tmp_path / "m.txt", "--quiet",
            "--mollify", 0.01, "--tufted")
    assert_close(ifem.heat_distance(V, F, 12, mollify=0.01, path="tufted"),
                 read_txt(tmp_path / "m.txt"))


def eigen_from_cli(tmp_path, path, k, *args):
    run_cli("eigen", path, "-k", k, "-o", tmp_path / "e.ply", "--quiet", *args)
    evals = read_txt(tmp_path / "e.eigenvalues.txt")
    _, _, info = ifem.read_mesh(tmp_path / "e.ply", return_info=True)
    props = info["vertex_properties"]
    return evals, np.column_stack([props[f"phi{j}"] for j in range(k)])


@pytest.mark.parametrize("kind", ["spot", "nonmanifold", "pointcloud"])
def test_eigen_matches_cli(tmp_path, kind):
    path, V, F, extra = inputs(kind, tmp_path)
    knn = {"knn": 12} if kind == "pointcloud" else {}
    evals_cli, evecs_cli = eigen_from_cli(tmp_path, path, 8, *extra)
    evals, evecs = ifem.eigen(V, F, k=8, **knn)
    assert evals.shape == (8,) and evecs.shape == (len(V), 8)
    assert_close(evals, evals_cli)
    assert_close(evecs, evecs_cli)


def test_eigen_refined_matches_cli(tmp_path):
    V, F = ifem.read_mesh(spot())
    evals_cli, evecs_cli = eigen_from_cli(tmp_path, spot(), 6, "--refine", "--resolution", 1)
    evals, evecs, info = ifem.eigen(V, F, 6, refine=True, resolution=1, return_info=True)
    assert info["refined"] and info["inserted_vertices"] > 0
    assert_close(evals, evals_cli)
    assert_close(evecs, evecs_cli)


def test_eigen_coarse_matches_cli_and_approximates(tmp_path):
    """Spectral coarsening (coarse=): the same pairs as `ifem eigen --coarse`, Ritz values
    above the exact ones and within a few % on spot, residuals reported; block iterations
    bring them to the exact ones."""
    V, F = ifem.read_mesh(spot())
    exact = ifem.eigen(V, F, 8)[0]
    evals_cli, evecs_cli = eigen_from_cli(tmp_path, spot(), 8, "--coarse", 600)
    evals, evecs, info = ifem.eigen(V, F, 8, coarse=600, return_info=True)
    assert_close(evals, evals_cli)
    assert_close(evecs, evecs_cli)
    assert info["eigen_coarse_vertices"] == 600 and info["eigen_residuals"].shape == (8,)
    assert (evals[1:] >= exact[1:] * (1 - 1e-9)).all()
    assert abs(evals[1:] / exact[1:] - 1).max() < 0.05
    refined = ifem.eigen(V, F, 8, coarse=600, coarse_iterations=4)[0]
    assert abs(refined[1:] / exact[1:] - 1).max() < 1e-6
    with pytest.raises(ifem.InvalidInput):
        ifem.eigen(V, F, 8, coarse=10)


def poisson_cli(tmp_path, path, f, bc, *args):
    np.savetxt(tmp_path / "f.txt", f, fmt="%.17g")
    with open(tmp_path / "bc.txt", "w") as out:
        for v, x in bc.items():
            out.write("%d %.17g\n" % (v, x))
    run_cli("poisson", path, "--rhs", tmp_path / "f.txt", "--dirichlet", tmp_path / "bc.txt",
            "-o", tmp_path / "u.txt", "--quiet", *args)
    return read_txt(tmp_path / "u.txt")


@pytest.mark.parametrize("kind", ["spot", "nonmanifold", "pointcloud"])
def test_poisson_matches_cli(tmp_path, kind):
    path, V, F, extra = inputs(kind, tmp_path)
    knn = {"knn": 12} if kind == "pointcloud" else {}
    f = np.sin(5 * V[:, 0]) + V[:, 1] ** 2
    bc = {0: 1.0, 57: -2.5, 300: 0.25}
    expected = poisson_cli(tmp_path, path, f, bc, *extra)
    assert_close(ifem.poisson(V, F, rhs=f, dirichlet=bc, **knn), expected)
    assert_close(ifem.poisson(V, F, f, (list(bc), list(bc.values())), **knn), expected)
    # screened, no Dirichlet data
    expected = poisson_cli(tmp_path, path, f, {}, "--screening", 2.5, *extra)
    assert_close(ifem.poisson(V, F, f, screening=2.5, **knn), expected)


def test_poisson_refined_matches_cli(tmp_path):
    V, F = ifem.read_mesh(spot())
    f = V[:, 2] - V[:, 0]
    bc = {5: 0.0, 2000: 1.0}
    expected = poisson_cli(tmp_path, spot(), f, bc, "--refine", "--resolution", 0.8)
    u, info = ifem.poisson(V, F, f, bc, refine=True, resolution=0.8, return_info=True)
    assert info["refined"] and info["correspondence"] == "integer"  # the default (D-330)
    assert_close(u, expected)


def test_poisson_refine_needs_signposts(tmp_path):
    V, F = ifem.read_mesh(nonmanifold(tmp_path))
    with pytest.raises(ifem.InvalidInput, match="signposts"):
        ifem.poisson(V, F, dirichlet={0: 1.0}, refine=True)


# --- analytic answers ---------------------------------------------------------------------------


def flat_distance_error(n, refine):
    V, F, _ = grid(n)
    c = (n // 2) * n + n // 2
    exact = np.linalg.norm(V - V[c], axis=1)
    far = exact > 0.25  # the heat method smooths the cone's tip: judge away from it
    d = ifem.heat_distance(V, F, c, refine=refine)
    return (abs(d - exact)[far] / exact[far]).max()


def test_flat_distance_is_euclidean():
    # On a plane the straight-line lower bound of the path bounds (docs/decisions.md D-141) is
    # the exact distance, and the heat method underestimates it there: the bound decides, to
    # rounding, on the input triangulation. Refined (--refine), the values read back are within
    # 4e-5 (the bound is not what decides there; not yet explained: see the issue-30 note). The
    # heat method's own convergence is tested unclamped in C++.
    plain = [flat_distance_error(n, False) for n in (21, 41)]
    assert max(plain) < 1e-12, plain
    refined = flat_distance_error(21, True)
    assert refined < 1e-4, refined


def test_sphere_eigenvalues():
    V, F = icosphere(3)  # 642 vertices
    evals, evecs = ifem.eigen(V, F, k=16)
    assert abs(evals[0]) < 1e-10
    for l, group in ((1, evals[1:4]), (2, evals[4:9]), (3, evals[9:16])):
        assert abs(group / (l * (l + 1)) - 1).max() < 0.02, (l, group)
    # a constant first mode; M-orthonormal modes
    assert np.ptp(evecs[:, 0]) < 1e-8 * abs(evecs[:, 0]).max()
    _, M = ifem.laplacian(V, F)
    assert abs(evecs.T @ (M @ evecs) - np.eye(16)).max() < 1e-8


def test_poisson_reproduces_linear_functions():
    V, F, inner = grid(15)
    u_exact = 2.0 * V[:, 0] - 3.0 * V[:, 1] + 0.5
    boundary = np.flatnonzero(~inner)
    u = ifem.poisson(V, F, dirichlet=(boundary, u_exact[boundary]))
    assert abs(u - u_exact).max() < 1e-10
    # screened: (L + cM) u = M (c u) for the same linear u
    u = ifem.poisson(V, F, rhs=4.0 * u_exact, dirichlet=(boundary, u_exact[boundary]),
                     screening=4.0)
    assert abs(u - u_exact).max() < 1e-10
    # pure Neumann: zero mass-weighted mean (f = 0 gives u = 0)
    assert abs(ifem.poisson(V, F)).max() < 1e-12


# --- the stateful solver, surface points --------------------------------------------------------


def test_solver_reuse_equals_one_offs():
    V, F = ifem.read_mesh(spot())
    solver = ifem.HeatDistanceSolver(V, F)
    assert solver.last_query_seconds == 0
    for sources in (0, [5], [1, 2000], np.arange(0, 2930, 97)):
        assert_close(solver.compute_distance(sources), ifem.heat_distance(V, F, sources),
                     rtol=1e-15)
    a = solver.compute_distance(7)
    solver.compute_distance([8, 9])
    assert (solver.compute_distance(7) == a).all()  # queries leave no state behind
    assert 0 < solver.last_query_seconds < 1


def test_solver_cuts_a_stray_hub_as_the_one_off(tmp_path):
    # spot's hub (largest star) pulled 1e4 diagonals away: the solver leaves its needle faces
    # out as heat_distance / `ifem distance` do (D-360, D-380), so the other distances barely
    # move (median 1.9e-2 uncut); vertex, batch and point queries agree with the one-off
    V, F = ifem.read_mesh(spot())
    area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    star = np.bincount(F.ravel(), np.repeat(area, 3), len(V))
    star[0] = 0
    hub = int(np.argmax(star))
    W = V.copy()
    W[hub] += 1e4 * np.linalg.norm(V.max(0) - V.min(0)) * np.array([0.6, 0.64, 0.48])
    clean, solver = ifem.HeatDistanceSolver(V, F), ifem.HeatDistanceSolver(W, F)
    assert not clean.info["stray_hubs_cut"] and solver.info["stray_hubs_cut"]
    d0, d = clean.compute_distance(0), solver.compute_distance(0)
    assert (d == ifem.heat_distance(W, F, 0)).all()
    off = np.arange(len(V)) != hub
    assert np.median(np.abs(d - d0)[off][1:] / d0[off][1:]) < 5e-3
    pulled = tmp_path / "pulled.obj"
    with open(pulled, "w") as out:
        out.writelines("v %.17g %.17g %.17g\n" % tuple(p) for p in W)
        out.writelines("f %d %d %d\n" % tuple(f + 1) for f in F)
    run_cli("distance", pulled, "--source", 0, "-o", tmp_path / "d.txt", "--quiet")
    assert_close(read_txt(tmp_path / "d.txt"), d, rtol=1e-12)
    D = solver.compute_distances([0, hub, 77])
    for j, s in enumerate([0, hub, 77]):
        assert_close(D[:, j], solver.compute_distance(s), rtol=1e-12)
    assert (np.abs(D[:, 1] - d)[off] > 0).any() and D[hub, 1] == 0  # from the hub: uncut
    # points: at vertex 0 on a kept face (located on the cut surface), at the hub on its star
    f0 = int(np.flatnonzero((F == 0).any(axis=1) & ~(F == hub).any(axis=1))[0])
    fh = int(np.flatnonzero((F == hub).any(axis=1))[0])
    for f, v in ((f0, 0), (fh, hub)):
        bary = (F[f] == v).astype(float)
        assert_close(solver.compute_distance(points=[(f, *bary)]), solver.compute_distance(v),
                     rtol=1e-10)


def test_points_next_to_a_cut_hub_whose_hole_takes_the_tufted_path():
    # spot's vertex of largest degree pulled away: the rest, with a hole, takes the tufted path
    # (obtuse angles at the rim), where no signposts locate points: they are located uncut
    # (this raised "did not come out edge for edge" before)
    V, F = ifem.read_mesh(spot())
    hub = int(np.argmax(np.bincount(F.ravel())))
    W = V.copy()
    W[hub] += 1e4 * np.ptp(V, axis=0).max()
    solver = ifem.HeatDistanceSolver(W, F)
    assert solver.info["stray_hubs_cut"]
    f = int(np.flatnonzero(~(F == hub).any(axis=1))[0])
    v = int(F[f, 0])
    d = solver.compute_distance(points=[(f, 1.0, 0.0, 0.0)])
    dv = solver.compute_distance(v)
    off = (np.arange(len(V)) != hub) & (dv > 0)
    assert d[v] == 0 and np.isfinite(d).all()
    assert np.median(np.abs(d - dv)[off] / dv[off]) < 5e-2


@pytest.mark.parametrize("kind", ["manifold", "nonmanifold", "cloud"])
def test_batched_sources_equal_single_queries_and_the_cli(tmp_path, kind):
    path = {"manifold": spot, "nonmanifold": lambda: nonmanifold(tmp_path),
            "cloud": lambda: point_cloud(tmp_path)}[kind]()
    V, F = ifem.read_mesh(path)
    solver = ifem.HeatDistanceSolver(V, F if F.size else None)
    n = solver.n_input_vertices
    sources = [0, n // 3, 7, 0, n - 1] + list(range(11, 11 + 40 * 29, 29))  # > one block of 32
    D = solver.compute_distances(np.array(sources, dtype=np.int64))
    assert D.shape == (n, len(sources))
    for j, s in enumerate(sources):
        d = solver.compute_distance(s)
        assert_close(D[:, j], d, rtol=1e-12)
        assert D[s, j] == 0
    assert (D[:, 0] == D[:, 3]).all()
    listed = tmp_path / "batch.txt"
    listed.write_text("".join("%d\n" % s for s in sources[:5]))
    run_cli("distance", path, "--sources-batch", listed, "-o", tmp_path / "D.npy", "--quiet")
    assert_close(np.load(tmp_path / "D.npy"), D[:, :5], rtol=1e-12)


def test_precision_double_matches_mixed_and_the_cli(tmp_path):
    V, F = ifem.read_mesh(spot())
    mixed = ifem.HeatDistanceSolver(V, F, precision="mixed")
    double = ifem.HeatDistanceSolver(V, F)
    assert (mixed.info["precision"], double.info["precision"]) == ("mixed", "double")
    for s in (0, 657):
        a, b = mixed.compute_distance(s), double.compute_distance(s)
        assert np.abs(a - b).max() < 1e-5 * b.max()
        assert_close(ifem.heat_distance(V, F, s, precision="mixed"), a, rtol=1e-15)
    run_cli("distance", spot(), "--source", "657", "--mixed-precision", "-o", tmp_path / "d.txt",
            "--quiet")
    assert_close(read_txt(tmp_path / "d.txt"), a, rtol=1e-9)
    with pytest.raises(ifem.InvalidInput, match="precision"):
        ifem.HeatDistanceSolver(V, F, precision="half")


def test_batched_sources_refuse_bad_ids():
    V, F = ifem.read_mesh(spot())
    solver = ifem.HeatDistanceSolver(V, F)
    with pytest.raises(ifem.InvalidInput, match="sources"):
        solver.compute_distances([0, 2930])
    with pytest.raises(ifem.InvalidInput):
        solver.compute_distances([])
    with pytest.raises(ifem.InvalidInput):
        solver.compute_distances([0.5, 1.0])


def test_points_at_vertices_equal_vertex_sources():
    V, F = ifem.read_mesh(spot())
    solver = ifem.HeatDistanceSolver(V, F)
    for f, corner in ((0, 0), (100, 2), (3000, 1)):
        bary = [0.0, 0.0, 0.0]
        bary[corner] = 1.0
        assert_close(solver.compute_distance(points=[(f, *bary)]),
                     solver.compute_distance(F[f, corner]), rtol=1e-10)
    # one-off with points gives the same as the solver
    p = [(10, 0.2, 0.3, 0.5), (2000, 0.6, 0.4, 0.0)]
    assert_close(ifem.heat_distance(V, F, points=p), solver.compute_distance(points=p))


@pytest.mark.parametrize("refine,correspondence",
                         [(False, "integer"), (True, "integer"), (True, "signposts")])
def test_points_are_located_on_the_flipped_triangulation(refine, correspondence):
    # On a flat grid the distance from a point p inside a face is |x − p| up to the heat
    # method's error, which is smooth and nearly a constant offset in the far field. A point
    # located in the wrong place shows there as a tilt: against a point moved by h/2, the
    # residual spreads by about h/2·(1/√2).
    n = 31
    h = 1.0 / (n - 1)
    V, F, _ = grid(n)
    # refined: located through the signposts, or through the common subdivision (integer)
    solver = ifem.HeatDistanceSolver(V, F, refine=refine, correspondence=correspondence)
    assert solver.info["correspondence"] == (correspondence if refine else None)
    assert solver.info["signposts"] == (refine and correspondence == "signposts")
    rng = np.random.default_rng(0)
    centre = np.flatnonzero(np.linalg.norm(V[F].mean(1)[:, :2] - 0.5, axis=1) < 0.1)
    for f in rng.choice(centre, 3, replace=False):
        bary = rng.dirichlet([1, 1, 1])
        p = bary @ V[F[f]]
        d = solver.compute_distance(points=[(f, *bary)])
        for moved, bound in ((0.0, (0.0, 0.1 * h)), (0.5 * h, (0.25 * h, np.inf))):
            exact = np.linalg.norm(V - (p + [moved, 0, 0]), axis=1)
            far = exact > 0.25
            assert bound[0] < np.std(d[far] - exact[far]) < bound[1], (f, bary, moved)


def test_point_sources_are_not_biased():
    # far from a point source, the distance is unbiased: its mean error is a small fraction of
    # h (the library once shifted a point source so that the linear blend of φ at the point was
    # 0; φ is a cone there, so every distance came out about 0.5·h too small)
    n = 31
    h = 1.0 / (n - 1)
    V, F, _ = grid(n, jitter=0.0)
    solver = ifem.HeatDistanceSolver(V, F)
    f = face_near(V, F, 0.5, 0.5)
    bary = np.array([1, 1, 1]) / 3
    p = bary @ V[F[f]]
    exact = np.linalg.norm(V - p, axis=1)
    far = exact > 0.25
    d = solver.compute_distance(points=[(f, *bary)])
    assert abs(np.mean(d[far] - exact[far])) < 0.1 * h
    g = face_near(V, F, 0.2, 0.3)
    q = bary @ V[F[g]]
    dg = solver.compute_distance(points=[(g, *bary)])
    exact_g = np.linalg.norm(V - q, axis=1)
    assert abs(np.mean(dg[exact_g > 0.25] - exact_g[exact_g > 0.25])) < 0.1 * h
    # two point sources (a zero-distance constraint between them, offsets included): near each
    # source the result is that source's own, as it is for two vertex sources (0.17·h here)
    d2 = solver.compute_distance(points=[(f, *bary), (g, *bary)])
    for single, centre in ((d, p), (dg, q)):
        near = np.linalg.norm(V - centre, axis=1) < 0.1
        assert np.abs(d2[near] - single[near]).max() < 0.25 * h


def test_points_refused_without_signposts(tmp_path):
    V, F = ifem.read_mesh(nonmanifold(tmp_path))
    solver = ifem.HeatDistanceSolver(V, F)
    with pytest.raises(ifem.InvalidInput, match="tufted"):
        solver.compute_distance(points=[(0, 0.2, 0.3, 0.5)])
    solver.compute_distance(0)  # vertex sources still work
    P, _ = ifem.read_mesh(point_cloud(tmp_path))
    with pytest.raises(ifem.InvalidInput, match="points"):
        ifem.HeatDistanceSolver(P, None, knn=12).compute_distance(points=[(0, 1, 0, 0)])


def test_reoriented_faces_keep_their_corners():
    # a face given clockwise is reoriented by the library; its point's coordinates must still
    # go with the corners as given
    V, F, _ = grid(9, jitter=0.0)
    F = F.copy()
    F[10] = F[10, ::-1]
    solver = ifem.HeatDistanceSolver(V, F)
    assert solver.info["reoriented_faces"] == 1
    b = (0.7, 0.2, 0.1)
    d = solver.compute_distance(points=[(10, *b)])
    flipped = solver.compute_distance(points=[(10, *b[::-1])])
    p = np.array(b) @ V[F[10]]
    exact = np.linalg.norm(V - p, axis=1)
    far = exact > 0.3
    assert np.std(d[far] - exact[far]) < np.std(flipped[far] - exact[far])


# --- argument checking --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def spot_mesh():
    return ifem.read_mesh(spot())


@pytest.mark.parametrize("call, error, words", [
    (lambda V, F: ifem.heat_distance(V, F, 5000), ifem.InvalidInput, "sources"),
    (lambda V, F: ifem.heat_distance(V, F, -1), ifem.InvalidInput, "sources"),
    (lambda V, F: ifem.heat_distance(V, F, []), ifem.InvalidInput, "sources is empty"),
    (lambda V, F: ifem.heat_distance(V, F, [1.0, 2.0]), ifem.InvalidInput,
     "sources must hold integers"),
    (lambda V, F: ifem.heat_distance(V, F, [[1, 2]]), ifem.InvalidInput, "sources"),
    (lambda V, F: ifem.heat_distance(V, F), ifem.InvalidInput, "sources"),
    (lambda V, F: ifem.heat_distance(V, F, 0, points=[(0, 1, 0, 0)]), ifem.InvalidInput, "points"),
    (lambda V, F: ifem.heat_distance(V, F, 0, path="manifld"), ifem.InvalidInput, "path"),
    (lambda V, F: ifem.heat_distance(V, F, 0, time_factor=0), ifem.InvalidInput, "time_factor"),
    (lambda V, F: ifem.heat_distance(V, F, 0, correction_steps=-1), ifem.InvalidInput,
     "correction_steps"),
    (lambda V, F: ifem.heat_distance(V, F, 0, correction_steps=1.5), ifem.InvalidInput,
     "correction_steps"),
    (lambda V, F: ifem.heat_distance(V, F, 0, mollify=float("nan")), ifem.InvalidInput, "mollify"),
    (lambda V, F: ifem.heat_distance(V, F, 0, min_angle=20), ifem.InvalidInput, "refine=True"),
    (lambda V, F: ifem.heat_distance(V, F, 0, refine=True, min_angle=40), ifem.InvalidInput,
     "min_angle"),
    (lambda V, F: ifem.heat_distance(V, F, 0, refine=True, resolution=-1), ifem.InvalidInput,
     "resolution"),
    (lambda V, F: ifem.heat_distance(V, F, 0, refine=True, max_insertions=-5), ifem.InvalidInput,
     "max_insertions"),
    (lambda V, F: ifem.heat_distance(V, F, points=[(6000, 1, 0, 0)]), ifem.InvalidInput,
     "points"),
    (lambda V, F: ifem.heat_distance(V, F, points=[(0, 0.5, 0.6, 0.1)]), ifem.InvalidInput,
     "barycentric"),
    (lambda V, F: ifem.heat_distance(V, F, points=[(0.5, 1, 0, 0)]), ifem.InvalidInput,
     "not an integer"),
    (lambda V, F: ifem.heat_distance(V, F, points=[(0, 1, 0)]), ifem.InvalidInput, "points"),
    (lambda V, F: ifem.heat_distance(V[:, :2], F, 0), ifem.InvalidInput, "V"),
    (lambda V, F: ifem.heat_distance(V, F + 10000, 0), ifem.InvalidInput, "F"),
    (lambda V, F: ifem.heat_distance(V[::2], None, 0, knn=1), ifem.InvalidInput, "knn"),
    (lambda V, F: ifem.eigen(V, F, k=len(V)), ifem.InvalidInput, "k must be in"),
    (lambda V, F: ifem.eigen(V, F, k=0), ifem.InvalidInput, "k must be in"),
    (lambda V, F: ifem.eigen(V, F, k=2.0), ifem.InvalidInput, "k must be an integer"),
    (lambda V, F: ifem.eigen(V, F, k=3, path="bogus"), ifem.InvalidInput, "path"),
    (lambda V, F: ifem.poisson(V, F, rhs=np.full(len(V), np.nan)), ifem.InvalidInput, "rhs"),
    (lambda V, F: ifem.poisson(V, F, rhs=np.ones(len(V) - 1)), ifem.InvalidInput, "rhs"),
    (lambda V, F: ifem.poisson(V, F, rhs=np.ones((len(V), 2))), ifem.InvalidInput, "rhs"),
    (lambda V, F: ifem.poisson(V, F, dirichlet={len(V): 1.0}), ifem.InvalidInput, "dirichlet"),
    (lambda V, F: ifem.poisson(V, F, dirichlet={3: np.inf}), ifem.InvalidInput, "dirichlet"),
    (lambda V, F: ifem.poisson(V, F, dirichlet=([3, 3], [1, 2])), ifem.InvalidInput, "dirichlet"),
    (lambda V, F: ifem.poisson(V, F, dirichlet=([3, 4], [1])), ifem.InvalidInput, "dirichlet"),
    (lambda V, F: ifem.poisson(V, F, dirichlet=[1, 2, 3]), ifem.InvalidInput, "dirichlet"),
    (lambda V, F: ifem.poisson(V, F, screening=-1), ifem.InvalidInput, "screening"),
])
def test_bad_arguments(spot_mesh, call, error, words):
    V, F = spot_mesh
    with pytest.raises(error, match=words):
        call(V, F)


def test_bad_arguments_of_the_solver(spot_mesh):
    V, F = spot_mesh
    solver = ifem.HeatDistanceSolver(V, F)
    with pytest.raises(ifem.InvalidInput, match=r"sources\[1\] = 2930 is out of range"):
        solver.compute_distance([0, 2930])
    with pytest.raises(ifem.InvalidInput, match="sources is empty"):
        solver.compute_distance(np.zeros(0, np.int64))
    with pytest.raises(ifem.InvalidInput, match="sources must hold integers"):
        solver.compute_distance(np.array([1.0]))
    with pytest.raises(ifem.InvalidInput, match="exactly one"):
        solver.compute_distance()
    with pytest.raises(ifem.NonManifoldInput, match="manifold"):
        ifem.HeatDistanceSolver(*ifem.read_mesh(test_data("fan3.obj")), path="manifold")
    # an exception class a plain-Python caller would catch
    with pytest.raises(ValueError):
        solver.compute_distance(-3)


# --- threads ------------------------------------------------------------------------------------


def test_gil_is_released():
    V, F, _ = grid(70)
    done = {}

    def work():
        t0 = time.perf_counter()
        done["solver"] = ifem.HeatDistanceSolver(V, F, refine=True)
        done["d"] = done["solver"].compute_distance(0)
        done["span"] = (t0, time.perf_counter())

    ticks = []
    worker = threading.Thread(target=work)
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
    worker.join()
    t0, t1 = done["span"]
    assert t1 - t0 > 0.05, "the call was too short to tell"
    inside = [t for t in ticks if t0 + 0.01 < t < t1 - 0.01]
    # Python ran throughout: no gap in the main thread's ticks longer than a switch interval
    # or so (a held GIL would stop it for the whole preparation)
    assert len(inside) > 1000
    assert np.diff([t0] + inside + [t1]).max() < 0.5 * (t1 - t0)


def test_concurrent_queries_agree():
    V, F = ifem.read_mesh(spot())
    solver = ifem.HeatDistanceSolver(V, F, refine=True)
    sources = [[0], [100, 200], [2500], [7, 8, 9]]
    serial = [solver.compute_distance(s) for s in sources]
    results = [None] * len(sources)

    def query(i):
        results[i] = solver.compute_distance(sources[i])

    threads = [threading.Thread(target=query, args=(i,)) for i in range(len(sources))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(results, serial):
        assert (a == b).all()
