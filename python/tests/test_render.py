"""ifem.render: the picture as an array (size, the sphere's colour order, isolines), the same
pixels as `ifem render` writes, file inputs with a property name, curves, and the refusals."""

import struct
import zlib

import numpy as np
import pytest

import ifem
from conftest import cli_path, run_cli, test_data


def sphere(n_lat=32, n_lon=64):
    V = [(0.0, 1.0, 0.0)]
    for i in range(1, n_lat):
        t = np.pi * i / n_lat
        for j in range(n_lon):
            p = 2 * np.pi * j / n_lon
            V.append((np.sin(t) * np.sin(p), np.cos(t), np.sin(t) * np.cos(p)))
    V.append((0.0, -1.0, 0.0))
    ring = lambda i, j: 1 + (i - 1) * n_lon + j % n_lon  # noqa: E731
    F = [(0, ring(1, j), ring(1, j + 1)) for j in range(n_lon)]
    for i in range(1, n_lat - 1):
        for j in range(n_lon):
            F += [(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)),
                  (ring(i, j), ring(i + 1, j + 1), ring(i, j + 1))]
    F += [(len(V) - 1, ring(n_lat - 1, j + 1), ring(n_lat - 1, j)) for j in range(n_lon)]
    return np.array(V), np.array(F)


def png_pixels(path):
    """H×W×3 array of an 8-bit RGB, filter-0 PNG (what ifem writes)."""
    data = path.read_bytes()
    pos, idat = 8, b""
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h = struct.unpack(">II", body[:8])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = np.frombuffer(zlib.decompress(idat), dtype=np.uint8).reshape(h, 1 + 3 * w)
    assert (raw[:, 0] == 0).all()
    return raw[:, 1:].reshape(h, w, 3)


def test_sphere_by_height():
    V, F = sphere()
    img, (lo, hi) = ifem.render(V, F, V[:, 1], size=(160, 120), return_range=True)
    assert img.shape == (120, 160, 3) and img.dtype == np.uint8
    assert (lo, hi) == (-1.0, 1.0)
    fg = (img != 255).any(axis=2)
    r = 0.9 * 60
    assert np.pi * (r * np.cos(np.pi / 32) - 1) ** 2 <= fg.sum() <= np.pi * (r + 1) ** 2
    share = img[..., 2] / np.maximum(img.sum(axis=2), 1)  # blue share: viridis low is violet
    assert share[:60][fg[:60]].mean() < share[60:][fg[60:]].mean()
    again = ifem.render(V, F, V[:, 1], size=(160, 120))
    assert np.array_equal(img, again)
    lines = ifem.render(V, F, V[:, 1], size=(160, 120), isolines=3, supersample=1)
    plain = ifem.render(V, F, V[:, 1], size=(160, 120), supersample=1)
    col = (lines[:, 80] != plain[:, 80]).any(axis=1)
    assert int((col[1:] & ~col[:-1]).sum() + col[0]) == 3
    with_legend = ifem.render(V, F, V[:, 1], size=(160, 120), legend=True)
    assert with_legend.shape == img.shape and (with_legend[:, -12:] != 255).any()
    assert (img[:, -12:] == 255).all()


def test_same_pixels_as_the_cli(tmp_path):
    cli_path()
    d = tmp_path / "d.ply"
    run_cli("distance", test_data("spot.obj"), "--source", 5, "-o", d, "--quiet")
    run_cli("render", d, "--size", "120x90", "--isolines", 4, "--view", "left", "-o",
            tmp_path / "cli.png", "--quiet")
    img = ifem.render(d, size=(120, 90), isolines=4, view="left", output=tmp_path / "py.png")
    assert np.array_equal(img, png_pixels(tmp_path / "cli.png"))
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    by_name = ifem.render(test_data("spot.obj"), size=(120, 90), view="left", isolines=4,
                          field=ifem.read_mesh(d, return_info=True)[2]["vertex_properties"]
                          ["distance"])
    assert np.array_equal(img, by_name)
    assert np.array_equal(img, ifem.render(d, field="distance", size=(120, 90), isolines=4,
                                           view="left"))


def test_curves_and_points(tmp_path):
    V, F = sphere(12, 24)
    a = np.linspace(-1.2, 1.2, 30)
    near = np.c_[np.sin(a), np.zeros_like(a), np.cos(a)]
    red = lambda img: ((img[..., 0] > 150) & (img[..., 1] < 100) & (img[..., 2] < 100)).sum()  # noqa: E731
    assert red(ifem.render(V, F, curves=[near], size=(100, 80))) > 20
    assert red(ifem.render(V, F, curves=[near * [1, 1, -1]], size=(100, 80))) == 0  # hidden
    (tmp_path / "c.obj").write_text("".join(f"v {x} {y} {z}\n" for x, y, z in near) +
                                    "l " + " ".join(str(i + 1) for i in range(30)) + "\n")
    assert red(ifem.render(V, F, curves=tmp_path / "c.obj", size=(100, 80))) > 20
    (tmp_path / "c.ply").write_text(
        f"ply\nformat ascii 1.0\nelement vertex 30\nproperty double x\nproperty double y\n"
        f"property double z\nelement edge 29\nproperty int vertex1\nproperty int vertex2\n"
        f"end_header\n" + "".join(f"{x} {y} {z}\n" for x, y, z in near) +
        "".join(f"{i} {i + 1}\n" for i in range(29)))
    from_ply = ifem.render(V, F, curves=str(tmp_path / "c.ply"), size=(100, 80))
    assert np.array_equal(from_ply, ifem.render(V, F, curves=tmp_path / "c.obj", size=(100, 80)))
    points = ifem.render(V, None, V[:, 1], size=(100, 80))
    assert 0 < (points != 255).any(axis=2).sum() < 100 * 80 / 2


def test_refusals():
    V, F = sphere(6, 8)
    with pytest.raises(ifem.InvalidInput, match="isolines need a field"):
        ifem.render(V, F, isolines=2)
    with pytest.raises(ifem.InvalidInput, match="unknown view 'side'"):
        ifem.render(V, F, view="side")
    with pytest.raises(ifem.InvalidInput, match="unknown colour map"):
        ifem.render(V, F, colormap="jet")
    with pytest.raises(ifem.InvalidInput, match="field must be a 1-D array of 42"):
        ifem.render(V, F, np.zeros(3))
    with pytest.raises(ifem.InvalidInput, match="width must be in"):
        ifem.render(V, F, size=(0, 10))
    with pytest.raises(ifem.InvalidInput, match="no per-vertex property 'x'"):
        ifem.render(test_data("spot.obj"), field="x")


def test_triangulation_edges_drawn_in_blue():
    """triangulation= draws the intrinsic edges as ifem.view traces them: blue pixels on a grey
    map, more after refinement than after flips only; another mesh's triangulation refused."""
    V, F = sphere(10, 20)
    blue = []
    for r in (None, ifem.refine(V, F, max_insertions=0), ifem.refine(V, F, resolution=0.5)):
        img = ifem.render(V, F, size=(320, 240), colormap="gray", triangulation=r).astype(int)
        blue.append(int(((img[..., 2] > img[..., 0] + 60) & (img[..., 2] > img[..., 1] + 30)).sum()))
    assert blue[0] == 0 and 1000 < blue[1] and blue[1] * 1.1 < blue[2], blue
    with pytest.raises(ifem.InvalidInput, match="another mesh"):
        ifem.render(V + 1.0, F, triangulation=ifem.refine(V, F, max_insertions=0))
