"""A point cloud's normals are used the same way by the CLI and Python (README, "One name per
operation"): a file's `nx ny nz` columns set the tangent planes in `ifem logmap` / `ifem
transport` / `ifem distance` and in `ifem.logmap(path)` / `ifem.transport(path)` /
`ifem.distance(path)` alike, and arrays with `normals=` give the same as the file."""

import numpy as np
import pytest

import ifem
from conftest import read_txt, run_cli, shared_data


def tilted_cloud(n=400):
    """n Fibonacci points on the unit sphere, with normals tilted by about 20° from the exact
    ones (so that PCA normals, close to the exact ones, give visibly different tangent
    planes)."""
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    r = np.sqrt(1 - z * z)
    t = np.pi * (1 + 5 ** 0.5) * i
    P = np.c_[r * np.cos(t), r * np.sin(t), z]
    tangent = np.cross(P, [0.3, 0.5, 0.8])
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    N = P + 0.36 * tangent
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    return P, N


@pytest.fixture
def cloud(tmp_path):
    P, N = tilted_cloud()
    path = tmp_path / "cloud.xyz"
    with open(path, "w") as f:
        for p, q in zip(P, N):
            f.write(" ".join(repr(float(x)) for x in (*p, *q)) + "\n")
    V, F, info = ifem.read_mesh(path, return_info=True)
    assert F.shape[0] == 0 and np.array_equal(info["normals"], N)
    return path, V, N


def test_logmap_python_equals_cli(cloud, tmp_path):
    path, V, N = cloud
    run_cli("logmap", path, "--source", 5, "-o", tmp_path / "lm.txt", "--quiet")
    cli = read_txt(tmp_path / "lm.txt")
    py = ifem.logmap(path, source=5)
    assert py.shape == cli.shape == (len(V), 2)
    np.testing.assert_allclose(py, cli, rtol=1e-9, atol=1e-12)
    # arrays with the same normals: the same map; without them (PCA normals): another one
    np.testing.assert_array_equal(ifem.logmap(V, normals=N, source=5), py)
    pca = ifem.logmap(V, source=5)
    assert np.abs(pca - cli).max() > 1e-3, "the file's normals were not used"


def test_transport_and_distance_python_equal_cli(cloud, tmp_path):
    path, V, N = cloud
    run_cli("transport", path, "--source", 7, "--vector", "1,0,0", "-o", tmp_path / "t.txt",
            "--quiet")
    np.testing.assert_allclose(ifem.transport(path, source=7, vector=[1, 0, 0]),
                               read_txt(tmp_path / "t.txt"), rtol=1e-9, atol=1e-12)
    run_cli("distance", path, "--source", 7, "-o", tmp_path / "d.txt", "--quiet")
    d = ifem.distance(path, sources=[7])
    np.testing.assert_allclose(d, read_txt(tmp_path / "d.txt"), rtol=1e-9, atol=1e-12)
    np.testing.assert_array_equal(ifem.distance(V, sources=[7], normals=N), d)


def test_a_path_takes_no_faces(cloud):
    path, V, _ = cloud
    with pytest.raises(ifem.InvalidInput, match="V must"):
        ifem.logmap(path, [[0, 1, 2]], source=0)


def test_field_python_equals_cli(cloud, tmp_path):
    path, V, N = cloud
    for n in (1, 4):
        run_cli("field", path, "--symmetry", n, "-o", tmp_path / "f.txt", "--quiet")
        cli = read_txt(tmp_path / "f.txt")
        py = ifem.field(path, symmetry=n)[0]
        np.testing.assert_allclose(py, cli, rtol=1e-9, atol=1e-12)
        np.testing.assert_array_equal(ifem.field(V, symmetry=n, normals=N)[0], py)
        # the field lies in the tangent planes of the file's normals, not of PCA's
        assert np.abs(np.sum(py * N, axis=1)).max() <= 1e-9
        assert np.abs(ifem.field(V, symmetry=n)[0] - cli).max() > 1e-3


# A real scan's normals (../shared/data, skipped when absent): bunny16k_points_normals.ply
# through a path, in Python and the CLI, for transport, field and logmap, the same numbers.
def test_scan_with_normals_python_equals_cli(tmp_path):
    path = shared_data("pointclouds/bunny16k_points_normals.ply")
    V, F, info = ifem.read_mesh(path, return_info=True)
    assert F.shape[0] == 0 and info["normals"].shape == V.shape
    run_cli("logmap", path, "--source", 0, "-o", tmp_path / "l.txt", "--quiet")
    np.testing.assert_allclose(ifem.logmap(path, source=0), read_txt(tmp_path / "l.txt"),
                               rtol=1e-9, atol=1e-12)
    run_cli("transport", path, "--source", 0, "--vector", "1,0,0", "-o", tmp_path / "t.txt",
            "--quiet")
    np.testing.assert_allclose(ifem.transport(path, source=0, vector=[1, 0, 0]),
                               read_txt(tmp_path / "t.txt"), rtol=1e-9, atol=1e-12)
    run_cli("field", path, "--symmetry", 2, "-o", tmp_path / "f.txt", "--quiet")
    np.testing.assert_allclose(ifem.field(path, symmetry=2)[0], read_txt(tmp_path / "f.txt"),
                               rtol=1e-9, atol=1e-12)
