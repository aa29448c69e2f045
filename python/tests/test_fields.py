"""direction_field: the same numbers as `ifem field` (1e-12), Poincaré–Hopf on spot for n = 1,
2, 4, unit tangent vectors, constraints held, fields along curves, and bad input; the frame
path (point clouds, nonmanifold meshes): the CLI's numbers, unit tangent vectors on a sphere
cloud, the log map's radius against the great-circle distance, finite fields on a nonmanifold
mesh."""

import numpy as np
import pytest

import ifem
from conftest import flat_grid, read_txt, run_cli, test_data


@pytest.fixture(scope="module")
def spot():
    return ifem.read_mesh(test_data("spot.obj"))


@pytest.mark.parametrize("n", [1, 4])
def test_matches_cli(spot, tmp_path, n):
    V, F = spot
    vectors, angle, singularity = ifem.direction_field(V, F, symmetry=n)
    run_cli("field", test_data("spot.obj"), "--symmetry", n, "-o", tmp_path / "f.txt", "--quiet")
    assert np.abs(vectors - read_txt(tmp_path / "f.txt")).max() <= 1e-12


@pytest.mark.parametrize("n", [1, 2, 4])
def test_poincare_hopf_and_unit_tangent_vectors(spot, n):
    V, F = spot
    vectors, angle, singularity, info = ifem.direction_field(V, F, symmetry=n, return_info=True)
    assert info["total_index"] == 2 * n  # spot has genus 0: χ = 2
    assert info["face_singularity"].shape == (len(F),)
    assert info["face_singularity"].sum() == 2 * n  # on the input's own faces too
    assert singularity.sum() == 2 * n  # every face of spot's IDT has an input vertex
    assert np.allclose(np.linalg.norm(vectors, axis=1), 1.0, atol=1e-12)
    # tangent: orthogonal to the area-weighted vertex normal
    e = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    normal = np.zeros_like(V)
    for k in range(3):
        np.add.at(normal, F[:, k], e)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    assert np.abs(np.sum(vectors * normal, axis=1)).max() < 1e-9


def test_constraint_is_held(spot):
    V, F = spot
    d = np.array([[1.0, 0.0, 0.0]])
    vectors, _, _ = ifem.direction_field(V, F, constraint_vertices=[0], directions=d)
    held = vectors[0]  # d projected to the tangent plane
    assert np.dot(vectors[0], d[0]) > 0.5
    other, _, _ = ifem.direction_field(V, F, constraint_vertices=[0], directions=-d)
    assert np.allclose(other[0], -held, atol=1e-9)


def test_bad_input(spot):
    V, F = spot
    with pytest.raises(ifem.InvalidInput, match="symmetry must be ≥ 1"):
        ifem.direction_field(V, F, symmetry=0)
    with pytest.raises(ifem.InvalidInput, match=r"constraint_vertices\[0\] = 5000"):
        ifem.direction_field(V, F, constraint_vertices=[5000], directions=[[1, 0, 0]])
    with pytest.raises(ifem.InvalidInput, match="one row per constraint vertex"):
        ifem.direction_field(V, F, constraint_vertices=[0, 1], directions=[[1, 0, 0]])
    with pytest.raises(ifem.InvalidInput, match="both vertices and directions"):
        ifem.direction_field(V, F, constraint_vertices=[0])
    # two different directions at one vertex, named by position (the same one twice is held)
    with pytest.raises(ifem.InvalidInput, match=r"constraint_vertices\[2\] \(vertex 5\): a "
                                                r"second, different direction at the vertex of "
                                                r"constraint_vertices\[0\]"):
        ifem.direction_field(V, F, constraint_vertices=[5, 7, 5],
                             directions=[[1, 0, 0], [0, 1, 0], [0, 1, 0]])
    ifem.direction_field(V, F, constraint_vertices=[5, 5], directions=[[1, 0, 0], [2, 0, 0]])
    with pytest.raises(ifem.InvalidInput, match="a point cloud has no boundary"):
        ifem.direction_field(V, align_boundary=True)
    # a nonmanifold mesh (the tufted path) is held along its input's boundary
    vectors, _, _, info = ifem.direction_field(*ifem.read_mesh(test_data("fan3.obj")),
                                               align_boundary=True, return_info=True)
    assert info["path"] == "tufted" and info["constrained"] > 0


def test_curves_match_cli(spot, tmp_path):
    V, F = spot
    (tmp_path / "c.txt").write_text("0 764 0 813\nbezier 0 2001 2000 126 300\n")
    curves = [ifem.Curve([764, 0, 813]), ifem.Curve([2001, 2000, 126, 300], bezier=True)]
    vectors, _, _, info = ifem.direction_field(V, F, symmetry=4, curves=curves,
                                               return_info=True)
    run_cli("field", test_data("spot.obj"), "--symmetry", 4, "--curves", tmp_path / "c.txt",
            "-o", tmp_path / "f.txt", "--quiet")
    assert np.abs(vectors - read_txt(tmp_path / "f.txt")).max() <= 1e-12
    assert info["total_index"] == 8
    assert info["curves"]["flipout"]["converged"]
    # a curves file's path works too
    again, _, _ = ifem.direction_field(V, F, symmetry=4, curves=tmp_path / "c.txt")
    assert np.array_equal(again, vectors)


# FlipOut's cap on the curves (--max-iterations): an error unless accept_partial
# (--accept-partial), then the CLI's field; refused without curves
def test_curves_iteration_cap_matches_cli(spot, tmp_path):
    V, F = spot
    (tmp_path / "c.txt").write_text("0 0 1500\n")
    with pytest.raises(ifem.InvalidInput, match=r"iteration cap \(3 reroutes.*accept"):
        ifem.field(V, F, symmetry=2, curves=tmp_path / "c.txt", max_iterations=3)
    vectors, _, _, info = ifem.field(V, F, symmetry=2, curves=tmp_path / "c.txt",
                                     max_iterations=3, accept_partial=True, return_info=True)
    assert info["curves"]["flipout"]["stopped_by"] == "iteration cap"
    run_cli("field", test_data("spot.obj"), "--symmetry", 2, "--curves", tmp_path / "c.txt",
            "--max-iterations", 3, "--accept-partial", "-o", tmp_path / "f.txt", "--quiet")
    assert np.abs(vectors - read_txt(tmp_path / "f.txt")).max() <= 1e-12
    with pytest.raises(ifem.InvalidInput, match="apply to curves"):
        ifem.field(V, F, accept_partial=True)


def test_straight_curve_holds_the_field_along_it():
    n, row = 12, 5
    V, F = flat_grid(n, straight_rows=(row,))
    on_row = row * (n + 1) + np.arange(n + 1)
    for symmetry in (1, 2):
        vectors, _, _ = ifem.direction_field(V, F, symmetry=symmetry,
                                             curves=ifem.Curve([on_row[0], on_row[-1]]))
        # the row's vertices lie on the curve (a straight line along x): held along it; for
        # n = 1 in the direction the curve runs, for n = 2 either way (a line)
        along = vectors[on_row] if symmetry == 1 else np.abs(vectors[on_row])
        assert np.abs(along - [1.0, 0.0, 0.0]).max() < 1e-9


def test_curves_bad_input(spot):
    V, F = spot
    with pytest.raises(ifem.InvalidInput, match=r"curves\[1\].*9999"):
        ifem.direction_field(V, F, curves=[ifem.Curve([0, 764]), ifem.Curve([1, 9999])])
    with pytest.raises(ifem.InvalidInput, match="edge-manifold, orientable mesh"):
        ifem.direction_field(*ifem.read_mesh(test_data("fan3.obj")), curves=[ifem.Curve([0, 2])])


def test_vector_heat_matches_cli(spot, tmp_path):
    V, F = spot
    solver = ifem.VectorHeatSolver(V, F)
    x = solver.transport(0, [1.0, 0.0, 0.0])
    run_cli("transport", test_data("spot.obj"), "--source", 0, "--vector", "1,0,0", "-o",
            tmp_path / "t.txt", "--quiet")
    assert np.abs(x - read_txt(tmp_path / "t.txt")).max() <= 1e-12
    uv = solver.log_map(7)
    run_cli("logmap", test_data("spot.obj"), "--source", 7, "-o", tmp_path / "l.txt", "--quiet")
    assert np.abs(uv - read_txt(tmp_path / "l.txt")).max() <= 1e-12
    assert np.all(uv[7] == 0)
    with pytest.raises(ifem.InvalidInput, match=r"source\[0\] = 5000|out of range"):
        solver.log_map(5000)


def sphere_cloud(n=2000):
    """n Fibonacci points on the unit sphere (their exact normals are their positions)."""
    i = np.arange(n)
    z = 1 - (2 * i + 1) / n
    r = np.sqrt(1 - z * z)
    g = np.pi * (3 - np.sqrt(5)) * i
    return np.column_stack([r * np.cos(g), r * np.sin(g), z])


def test_point_cloud_matches_cli(spot, tmp_path):
    V, _ = spot
    np.savetxt(tmp_path / "spot.xyz", V, fmt="%.17g")
    vectors, _, singularity, info = ifem.direction_field(V, symmetry=4, return_info=True)
    run_cli("field", tmp_path / "spot.xyz", "--symmetry", 4, "-o", tmp_path / "f.txt", "--quiet")
    assert info["path"] == "pointcloud"
    assert np.abs(vectors - read_txt(tmp_path / "f.txt")).max() <= 1e-12
    assert np.all(singularity == 0)
    solver = ifem.VectorHeatSolver(V)
    x = solver.transport(0, [0.0, 0.0, 1.0])
    run_cli("transport", tmp_path / "spot.xyz", "--source", 0, "--vector", "0,0,1", "-o",
            tmp_path / "t.txt", "--quiet")
    assert np.abs(x - read_txt(tmp_path / "t.txt")).max() <= 1e-12
    uv = solver.log_map(3)
    run_cli("logmap", tmp_path / "spot.xyz", "--source", 3, "-o", tmp_path / "l.txt", "--quiet")
    assert np.abs(uv - read_txt(tmp_path / "l.txt")).max() <= 1e-12


def test_sphere_cloud_fields_are_unit_tangent_and_the_log_map_is_the_great_circle_map():
    P = sphere_cloud()
    for k in (8, 16):
        vectors, _, _, info = ifem.direction_field(P, knn=k, return_info=True)
        assert info["orientation_conflicts"] == 0
        assert np.allclose(np.linalg.norm(vectors, axis=1), 1, atol=1e-9)
        assert np.abs(np.sum(vectors * P, axis=1)).max() < 0.05
    solver = ifem.VectorHeatSolver(P, normals=P)
    x = solver.transport(0, [1.0, 0.0, 0.0])
    assert np.abs(np.sum(x * P, axis=1)).max() < 1e-9  # the given normals are exact
    uv = solver.log_map(0)
    exact = np.arccos(np.clip(P @ P[0], -1, 1))
    keep = (exact > 0.15) & (exact < np.pi - 0.3)
    radius = np.linalg.norm(uv, axis=1)
    assert np.mean(np.abs(radius[keep] - exact[keep]) / exact[keep]) < 0.03


def test_nonmanifold_mesh_fields_are_finite():
    V, F = ifem.read_mesh(test_data("triple_vierbein.obj"))
    vectors, _, _, info = ifem.direction_field(V, F, symmetry=2, return_info=True)
    assert info["path"] == "tufted"
    assert np.isfinite(vectors).all()
    assert np.allclose(np.linalg.norm(vectors, axis=1), 1, atol=1e-9)
    solver = ifem.VectorHeatSolver(V, F)
    assert np.isfinite(solver.transport(0, [0.0, 0.0, 1.0])).all()
    assert np.isfinite(solver.log_map(0)).all()


def soup_pieces(V, F):
    """Each vertex's piece, counted from the faces alone (scipy's connected components), and the
    pieces without area."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    n = len(V)
    rows = np.r_[F[:, 0], F[:, 1], F[:, 2]]
    cols = np.r_[F[:, 1], F[:, 2], F[:, 0]]
    count, piece = connected_components(coo_matrix((np.ones(len(rows)), (rows, cols)), (n, n)),
                                        directed=False)
    area = np.zeros(count)
    np.add.at(area, piece[F[:, 0]], np.linalg.norm(
        np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1) / 2)
    return piece, count, np.flatnonzero(area == 0)


# A triangle soup (tests/data/soup_icosphere.obj: 8 pieces of an icosphere with their own
# coincident vertices, a lone flat triangle, a zero-area face), on the manifold and tufted
# paths: a field for n = 1, 2, 4 with unit vectors on the pieces with area and 0 on the
# zero-area one, the components counted as here, the CLI's numbers; transport finite on the
# source's piece and NaN elsewhere, as the CLI writes it.
@pytest.mark.parametrize("path", ["auto", "tufted"])
def test_triangle_soup(tmp_path, path):
    soup = test_data("soup_icosphere.obj")
    V, F = ifem.read_mesh(soup)
    piece, count, flat = soup_pieces(V, F)
    assert (count, len(flat)) == (10, 1)
    no_field = np.isin(piece, flat)
    opts = [] if path == "auto" else ["--tufted"]
    for n in (1, 2, 4):
        vectors, _, _, info = ifem.field(V, F, symmetry=n, path=path, return_info=True)
        assert (info["components"], info["free_components"], info["empty_components"],
                info["flat_components"]) == (count, count - len(flat), len(flat), len(flat))
        np.testing.assert_allclose(np.linalg.norm(vectors, axis=1), np.where(no_field, 0, 1),
                                   atol=1e-9)
        run_cli("field", soup, "--symmetry", n, "-o", tmp_path / "f.txt", "--quiet", *opts)
        np.testing.assert_allclose(vectors, read_txt(tmp_path / "f.txt"), atol=1e-12)
    for source in (0, 240):
        x = ifem.transport(soup, source=source, vector=[1, 0, 0], path=path)
        reached = piece == piece[source]
        assert np.isfinite(x[reached]).all()
        np.testing.assert_allclose(np.linalg.norm(x[reached], axis=1),
                                   np.linalg.norm(x[source]), rtol=1e-9)
        assert np.isnan(x[~reached]).all()
        run_cli("transport", soup, "--source", source, "--vector", "1,0,0", "-o",
                tmp_path / "t.txt", "--quiet", *opts)
        np.testing.assert_array_equal(np.isnan(read_txt(tmp_path / "t.txt")), np.isnan(x))
        np.testing.assert_allclose(read_txt(tmp_path / "t.txt")[reached], x[reached],
                                   atol=1e-12)


# ifem.logmap(method=...): the affine method is the identity map (up to one rotation) on a flat
# jittered square with its corners; a second copy and an unreferenced vertex are (nan, nan) with
# distance inf, in both methods; a bad method is refused; the CLI's --method gives the same map
def test_logmap_methods_and_unreached(tmp_path):
    V, F = flat_grid(16)
    n = len(V)
    V2 = np.r_[V, V + [2.0, 0, 0], [[-5.0, 0, 0]]]
    F2 = np.r_[F, F + n]
    src = 8 * 17 + 8
    for method in ("affine", "vector-heat", "blend"):
        uv, d = ifem.logmap(V2, F2, source=src, method=method, return_distance=True)
        assert uv.shape == (2 * n + 1, 2) and d.shape == (2 * n + 1,)
        assert np.all(np.isnan(uv[n:])) and np.all(np.isinf(d[n:]))
        assert np.all(np.isfinite(uv[:n])) and np.all(d[:n][np.arange(n) != src] > 0)
        assert np.all(uv[src] == 0)
    uv = ifem.logmap(V, F, source=src, method="affine")
    exact = (V[:, 0] - V[src, 0]) + 1j * (V[:, 1] - V[src, 1])
    z = uv[:, 0] + 1j * uv[:, 1]
    keep = np.abs(exact) > 0
    rot = np.mean(z[keep] / exact[keep])
    rot /= abs(rot)
    assert np.abs(z / rot - exact).max() <= 1e-9
    # the library's one parser (solvers::log_map_method_from), as `logmap --method` says it
    with pytest.raises(ifem.InvalidInput,
                       match="method = 'exact': expected 'blend', 'affine' or 'vector-heat'"):
        ifem.logmap(V, F, source=src, method="exact")
    path = tmp_path / "grid.obj"
    with open(path, "w") as f:
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)
    run_cli("logmap", path, "--source", src, "--method", "affine", "-o", tmp_path / "l.txt",
            "--quiet")
    assert np.abs(read_txt(tmp_path / "l.txt") - ifem.logmap(str(path), source=src,
                                                              method="affine")).max() <= 1e-12
