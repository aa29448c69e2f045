"""read_mesh / write_ply round trips, and bad input: every malformed array or file is a clear
Python exception of the right class (never a crash), and convertible layouts are accepted."""

import threading
import time

import numpy as np
import pytest

import ifem
from conftest import test_data


@pytest.fixture(scope="module")
def spot():
    return ifem.read_mesh(test_data("spot.obj"))


def test_read_mesh_shapes_and_info(spot):
    V, F = spot
    assert V.shape == (2930, 3) and V.dtype == np.float64 and V.flags.c_contiguous
    assert F.shape == (5856, 3) and F.dtype == np.int32
    assert F.min() == 0 and F.max() == len(V) - 1
    _, _, info = ifem.read_mesh(str(test_data("spot.obj")), return_info=True)
    assert info["format"] == "obj" and info["polygons"] == 5856


def test_write_ply_round_trip(tmp_path, spot):
    V, F = spot
    d = np.linalg.norm(V - V[0], axis=1)
    for binary in (True, False):
        p = tmp_path / f"out_{binary}.ply"
        ifem.write_ply(p, V, F, binary=binary, distance=d, index=np.arange(len(V)))
        V2, F2, info = ifem.read_mesh(p, return_info=True)
        assert np.array_equal(F2, F)
        assert np.array_equal(V2, V)  # doubles written with full precision
        props = info["vertex_properties"]
        assert np.array_equal(props["distance"], d)
        assert np.array_equal(props["index"], np.arange(len(V)))
    cloud = tmp_path / "cloud.ply"
    ifem.write_ply(cloud, V[:10])
    P, Fp = ifem.read_mesh(cloud)
    assert P.shape == (10, 3) and Fp.shape == (0, 3)


def test_bad_files_raise_ioerror(tmp_path):
    with pytest.raises(OSError, match="cannot open"):
        ifem.read_mesh(tmp_path / "missing.obj")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    with pytest.raises(ifem.IoError, match=r"bad\.obj.*4"):  # file and line
        ifem.read_mesh(bad)
    with pytest.raises(ifem.IoError):
        ifem.read_mesh(tmp_path / "mesh.unknown")
    with pytest.raises(ifem.IoError):
        ifem.write_ply(tmp_path / "no" / "such" / "dir.ply", np.zeros((3, 3)), [[0, 1, 2]])


def test_exception_hierarchy():
    assert issubclass(ifem.InvalidInput, ValueError) and issubclass(ifem.InvalidInput, ifem.Error)
    assert issubclass(ifem.NonManifoldInput, ifem.InvalidInput)
    assert issubclass(ifem.NonOrientableInput, ifem.NonManifoldInput)
    assert issubclass(ifem.IoError, OSError) and issubclass(ifem.SolverError, RuntimeError)


def test_convertible_layouts_are_accepted(spot):
    V, F = spot
    L, M = ifem.laplacian(V, F)
    variants = [
        (np.asfortranarray(V), F),                   # Fortran order
        (V, F.astype(np.int64)),                      # int64 ids
        (V, F.astype(np.uint16)),                     # unsigned ids
        (V.tolist(), F.tolist()),                     # nested lists
        (np.repeat(V, 2, axis=0)[::2], F),            # a strided view
    ]
    for Vx, Fx in variants:
        Lx, Mx = ifem.laplacian(Vx, Fx)
        assert abs(Lx - L).max() == 0 and abs(Mx - M).max() == 0
    L32, _ = ifem.laplacian(V.astype(np.float32), F)  # float32 positions: converted, close
    assert abs(L32 - L).max() < 1e-3 * abs(L).max()


@pytest.mark.parametrize("bad_V, message", [
    (np.zeros((5, 2)), r"V must be an n×3 array.*\(5, 2\)"),
    (np.zeros(9), r"V must be an n×3 array.*\(9,\)"),
    (np.zeros((0, 3)), "V is empty"),
    (np.array([["a", "b", "c"]] * 3), "V must hold real numbers"),
    (np.array([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]]), "V row 1 is not finite"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, np.inf, 0]]), "V row 2 is not finite"),
    (None, "V is None"),
    ("not an array", "V must"),
])
def test_bad_positions(bad_V, message):
    with pytest.raises(ifem.InvalidInput, match=message):
        ifem.laplacian(bad_V, [[0, 1, 2]])


@pytest.mark.parametrize("bad_F, message", [
    ([[0, 1, 3]], r"F row 0 has vertex id 3, out of range \[0, 3\)"),
    ([[0, 1, -1]], "F row 0 has vertex id -1"),
    ([[0.0, 1.0, 2.0]], "F must hold integers, got dtype float64"),
    ([[0, 1]], r"F must be an n×3 array.*\(1, 2\)"),
    (np.zeros((0, 3), int), "F has no faces"),
    ([[0, 1, 2], [0, 1, 2**40]], "F row 1 has vertex id 1099511627776"),
])
def test_bad_faces(bad_F, message):
    V = np.eye(3)
    with pytest.raises(ifem.InvalidInput, match=message):
        ifem.laplacian(V, bad_F)


def test_bad_options(spot):
    V, F = spot
    with pytest.raises(ifem.InvalidInput, match="path must be"):
        ifem.laplacian(V, F, path="sideways")
    with pytest.raises(ifem.InvalidInput, match="mollif"):
        ifem.laplacian(V, F, mollify=-1.0)
    with pytest.raises(ifem.InvalidInput, match=r"k must be in \[2, number of points\)"):
        ifem.point_cloud_laplacian(V[:10], k=10)
    with pytest.raises(ifem.InvalidInput, match="normals must have one row per point"):
        ifem.point_cloud_laplacian(V[:50], k=8, normals=np.ones((3, 3)))
    with pytest.raises(ifem.InvalidInput, match="vertex property 'd' has 3 values"):
        ifem.write_ply("/tmp/never.ply", V, F, d=np.zeros(3))


def test_manifold_path_refuses_nonmanifold():
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0.2], [0.5, 0.1, 1]], float)
    F = [[0, 1, 2], [1, 0, 3], [0, 1, 4]]
    with pytest.raises(ifem.NonManifoldInput, match="path='manifold'"):
        ifem.laplacian(V, F, path="manifold")
    L, M, info = ifem.laplacian(V, F, return_info=True)
    assert info["path"] == "tufted" and L.shape == (5, 5)


def test_results_own_their_memory(spot):
    # zero-copy results must stay valid after everything else is gone
    V, F = spot
    L, M = ifem.laplacian(V.copy(), F.copy())
    import gc
    gc.collect()
    assert np.isfinite(L.data).all() and abs(L @ np.ones(len(V))).max() < 1e-10


def grid_mesh(n):
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    V = np.c_[x.ravel(), y.ravel(), 0.1 * np.sin(5 * x.ravel()) * y.ravel()]
    a = (np.arange(n - 1)[None, :] + n * np.arange(n - 1)[:, None]).ravel()
    F = np.r_[np.c_[a, a + 1, a + n + 1], np.c_[a, a + n + 1, a + n]]
    return V, F


def test_gil_is_released_during_computation():
    V, F = grid_mesh(300)  # 178k faces: each call takes tens of milliseconds
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.0005)

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.01)
    start = time.perf_counter()
    for _ in range(3):
        ifem.laplacian(V, F)
    end = time.perf_counter()
    done.set()
    t.join()
    gaps = np.diff([start] + [x for x in ticks if start < x < end] + [end])
    # with the GIL held during a call the counter would stall for the whole call; released,
    # it keeps ticking (the longest pause is the checked conversion of V and F, a few ms)
    assert gaps.max() < 0.5 * (end - start) / 3, (gaps.max(), end - start)


@pytest.mark.parametrize("mesh", ["spot.obj", "triple_vierbein.obj", "fan3.obj"])
def test_mesh_info_matches_cli_json(mesh):
    import json
    from conftest import run_cli
    path = test_data(mesh)
    expected = json.loads(run_cli("info", path, "--json", "--quiet"))
    V, F = ifem.read_mesh(path)
    info = ifem.mesh_info(V, F)
    for key, value in expected.items():
        if key in ("file", "format", "polygons"):
            continue  # what the file was: mesh_info sees arrays
        assert key in info, key
        if isinstance(value, float):
            assert info[key] == pytest.approx(value, rel=1e-12, abs=1e-300), key
        else:
            assert info[key] == value, key


def test_mesh_info_knows_the_topology():
    info = ifem.mesh_info(*ifem.read_mesh(test_data("spot.obj")))
    assert (info["genus"], info["components"], info["boundary_loops"]) == (0, 1, 0)
    assert info["euler_characteristic"] == 2 and info["path"] == "manifold"
    nm = ifem.mesh_info(*ifem.read_mesh(test_data("triple_vierbein.obj")))
    assert nm["nonmanifold_edges"] == 20 and nm["genus"] is None and nm["path"] == "tufted"
    V, _ = ifem.read_mesh(test_data("spot.obj"))
    for k in (6, 12):
        cloud = ifem.mesh_info(V, None, knn=k)
        assert cloud["path"] == "pointcloud" and cloud["points"] == len(V) and cloud["k"] == k
