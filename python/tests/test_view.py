"""ifem.view: the same page as `ifem view` (same scene for the same data), its fields, glyphs,
curves and a refined triangulation's traced edges (one per intrinsic edge, ends at the edge's
vertices), and its refusals. Skips when three.js is not installed (scripts/setup.sh)."""

import base64
import json
import re
import struct

import numpy as np
import pytest

import ifem
from conftest import run_cli, test_data


def scene_of(page):
    text = page.read_text()
    m = re.search(r'<script id="ifem-scene" type="application/json">(.*?)</script>', text, re.S)
    return json.loads(m.group(1))


def floats(b64):
    raw = base64.b64decode(b64)
    return np.array(struct.unpack(f"<{len(raw) // 4}f", raw))


def view(*args, **kwargs):
    try:
        return ifem.view(*args, **kwargs)
    except ifem.IoError as e:
        if "three.js not found" in str(e):
            pytest.skip("three.js is not installed: scripts/setup.sh (npm install three)")
        raise


def bent_grid(n=6):
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    V = np.c_[x.ravel() + 0.7 * y.ravel(), y.ravel(), 0.2 * np.sin(3 * x.ravel())]
    F = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            F += [(a, a + 1, a + n + 2), (a, a + n + 2, a + n + 1)]
    return V, np.array(F)


def test_same_scene_as_the_cli(tmp_path):
    spot = test_data("spot.obj")
    V, _ = ifem.read_mesh(spot)
    d = V[:, 1] ** 2
    np.savetxt(tmp_path / "d.txt", d, fmt="%.17g")
    run_cli("view", spot, "--field", tmp_path / "d.txt", "--units", "m", "--title", "spot",
            "-o", tmp_path / "cli.html", "--quiet")
    info = view(spot, path=tmp_path / "py.html", title="spot", units="m", d=d)
    assert info["fields"] == 1 and info["path"] == str(tmp_path / "py.html")
    assert scene_of(tmp_path / "py.html") == scene_of(tmp_path / "cli.html")


def test_fields_glyphs_curves(tmp_path):
    V, F = bent_grid()
    h = V[:, 2].copy()
    h[3] = np.inf  # drawn grey; the range is over the finite values
    vec = np.tile([1.0, 0.0, 0.0], (len(V), 1))
    sing = np.zeros(len(V))
    sing[10] = 0.25
    info = view(V, F, tmp_path / "v.html", height=h, vectors=vec, symmetry=4, singularity=sing,
                curves={"diag": [V[[0, 8, 16]]], "edge": [V[:3], V[3:5]]})
    assert info["glyphs"] == 4 * len(V) and info["singularities"] == 1 and info["curves"] == 2
    s = scene_of(tmp_path / "v.html")
    f = {x["name"]: x for x in s["fields"]}
    assert set(f) == {"height", "fx", "fy", "fz", "singularity"}
    finite = np.delete(V[:, 2], 3)
    assert f["height"]["min"] == finite.min() and f["height"]["max"] == finite.max()
    assert np.isnan(floats(f["height"]["values"])[3])
    assert [c["name"] for c in s["curves"]] == ["diag", "edge"]
    with pytest.raises(ifem.InvalidInput, match="one per vertex"):
        view(V, F, tmp_path / "bad.html", height=h[:-1])
    with pytest.raises(ifem.InvalidInput, match="symmetry"):
        view(V, F, tmp_path / "bad.html", vectors=vec, symmetry=7)
    with pytest.raises(ifem.IoError, match="three.js not found"):
        ifem.view(V, F, tmp_path / "bad.html", three_dir=tmp_path / "nowhere")
    assert not (tmp_path / "bad.html").exists()


def test_triangulation_edges(tmp_path):
    V, F = bent_grid()
    r = ifem.refine(V, F, min_angle=25, resolution=0.6)  # inserts vertices
    edges = r.traced_edges()
    Fi = r.faces()
    unique = {tuple(sorted(e)) for t in Fi for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    assert len(edges) == len(unique) and r.n_vertices > len(V)
    P = r.positions()
    ends = {tuple(sorted((int(np.argmin(np.linalg.norm(P - e[0], axis=1))),
                          int(np.argmin(np.linalg.norm(P - e[-1], axis=1)))))) for e in edges}
    assert ends == unique
    info = view(V, F, tmp_path / "t.html", triangulation=r)
    assert info["intrinsic_edges"] == len(edges)
    with pytest.raises(ifem.InvalidInput, match="another mesh"):
        view(V + 1.0, F, tmp_path / "t2.html", triangulation=r)
