"""ifem.trace / ifem.trace_geodesic (straight geodesics from a point): exact straight segments
on a jittered flat grid from vertices and face points, the end point starting the next ray, a
helix on a prism against its unrolled line, the CLI's figures, and every refusal."""

import math

import numpy as np
import pytest

import ifem
from conftest import flat_grid, run_cli


def prism(n=12, rings=20, h=0.5):
    """An open prism of n sides (circumradius 1): its side unrolls onto a strip of width n·s."""
    a = 2 * np.pi * np.arange(n) / n
    V = np.array([(math.cos(t), math.sin(t), i * h) for i in range(rings + 1) for t in a])
    F = []
    for i in range(rings):
        for j in range(n):
            p, q = i * n + j, i * n + (j + 1) % n
            F += [(p, q, q + n), (p, q + n, p + n)]
    return V, np.array(F)


def test_flat_grid_rays_are_straight_and_exact():
    V, F = flat_grid(10)
    rng = np.random.default_rng(5)
    interior = [v for v in range(len(V)) if 0.3 < V[v, 0] < 0.7 and 0.3 < V[v, 1] < 0.7]
    for k in range(20):
        a = rng.uniform(0, 2 * np.pi)
        d = np.array([math.cos(a), math.sin(a), 0.0])
        if k % 2:
            start = int(interior[k % len(interior)])
            x0 = V[start]
        else:
            f = int(rng.integers(len(F)))
            b = rng.dirichlet([1, 1, 1])
            while not all(0.25 < (b @ V[F[f]])[:2]) or not all((b @ V[F[f]])[:2] < 0.75):
                f = int(rng.integers(len(F)))
            start, x0 = (f, *b), b @ V[F[f]]
        r = ifem.trace(V, F, start, d + [0, 0, 0.3], 0.2)
        assert abs(r.length - 0.2) < 1e-12
        assert np.linalg.norm(r.end_position - (x0 + 0.2 * d)) < 1e-12
        assert np.linalg.norm(r.polyline[-1] - r.end_position) < 1e-15
        assert np.linalg.norm(r.start_direction - d) < 1e-12
        off = r.polyline - x0
        assert np.abs(off[:, 0] * d[1] - off[:, 1] * d[0]).max() < 1e-12
        face, *bary = r.end
        assert np.linalg.norm(np.array(bary) @ V[F[face]] - r.end_position) < 1e-14
        # the end starts the way back
        back = ifem.trace_geodesic(V, F, r.end, -d, 0.2)
        assert np.linalg.norm(back.end_position - x0) < 1e-12


def test_several_directions_and_the_cli_agree(tmp_path):
    V, F = flat_grid(6, jitter=0.0)
    dirs = np.array([[1.0, 0, 0], [0, 1, 0], [-1, -1, 0]])
    rays = ifem.trace(V, F, (7, 0.2, 0.3, 0.5), dirs, 0.3)
    assert isinstance(rays, list) and len(rays) == 3
    path = tmp_path / "grid.obj"
    with open(path, "w") as f:
        for v in V:
            f.write("v %.17g %.17g %.17g\n" % tuple(v))
        for t in F:
            f.write("f %d %d %d\n" % tuple(t + 1))
    import json
    for d, r in zip(dirs, rays):
        doc = json.loads(run_cli("trace", path, "--from", "face:7:0.3:0.5", "--direction",
                                 ",".join(map(repr, d)), "--length", "0.3", "--json", "--quiet"))
        assert np.linalg.norm(np.array(doc["rays"][0]["end"]["position"]) - r.end_position) < 1e-15
    # a path is read as the CLI reads it
    assert np.linalg.norm(ifem.trace(str(path), None, 7, [1, 0, 0], 0.1).end_position -
                          (V[7] + [0.1, 0, 0])) < 1e-12


def test_prism_helix_unrolls():
    V, F = prism()
    n, s = 12, 2 * math.sin(math.pi / 12)
    climb = 0.15
    lu, lz = math.cos(math.atan(climb)), math.sin(math.atan(climb))
    along = (V[1] - V[0]) / s
    length = 2.5 * n * s
    # face 48: corners (24, 25, 37); b = (0.6, 0.2, 0.2): unrolled (0.4 s, 1.1)
    r = ifem.trace(V, F, (48, 0.6, 0.2, 0.2), lu * along + [0, 0, lz], length)
    u, z = 0.4 * s + length * lu, 1.1 + length * lz
    u %= n * s
    k = int(u // s)
    t = (u - k * s) / s
    want = (1 - t) * V[k % n] + t * V[(k + 1) % n]
    want[2] = z
    assert np.linalg.norm(r.end_position - want) < 1e-11
    assert abs(r.length - length) < 1e-12 * length


def test_boundary_stop_and_slide():
    V, F = flat_grid(6, jitter=0.0)
    r = ifem.trace(V, F, (7, 0.2, 0.3, 0.5), [1, 0, 0], 5.0)
    assert r.hit_boundary and r.length < 1 and abs(r.end_position[0] - 1) < 1e-12
    s = ifem.trace(V, F, (7, 0.2, 0.3, 0.5), [1, 0.2, 0], 5.0, slide=True)
    assert s.slides > 0 and s.length > r.length


@pytest.mark.parametrize("kwargs,match", [
    (dict(start=3, direction=[0, 0, 0], length=1), "nonzero"),
    (dict(start=3, direction=[0, 0, 1], length=1), "normal"),
    (dict(start=3, direction=[1, 0, 0], length=-1), "length"),
    (dict(start=99, direction=[1, 0, 0], length=1), "out of range"),
    (dict(start=(500, 1, 0, 0), direction=[1, 0, 0], length=1), "out of range"),
    (dict(start="x", direction=[1, 0, 0], length=1), "vertex id"),
    (dict(start=3, direction=[[1, 0]], length=1), "shape"),
    (dict(start=1, direction=[0, -1, 0], length=1), "off the surface"),
])
def test_refusals(kwargs, match):
    V, F = flat_grid(6, jitter=0.0)
    with pytest.raises(ifem.InvalidInput, match=match):
        ifem.trace(V, F, **kwargs)


def test_nonmanifold_is_refused():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1.0]])
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    with pytest.raises(ifem.NonManifoldInput):
        ifem.trace(V, F, 0, [0, 1, 0], 0.5)
