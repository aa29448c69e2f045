"""`ifem view`: the page is one self-contained file (no external script, style or link; the
scene's arrays decode to the input's vertices and the fields' values), intrinsic edges and
curves are counted as given, bad inputs are refused, and, in headless Chromium (skipped when
Debian's chromium is absent) with the network blocked: the canvas is not blank, the legend shows
the property's min / max, switching the property changes pixels, and no request leaves the page.

The page needs three.js (scripts/setup.sh installs it with npm into build/web): without it the
tests that write pages skip, naming the command that installs it."""

import base64
import json
import os
import pathlib
import re
import shutil
import struct
import subprocess

import pytest

from clitools import SPOT_VERTICES, numbers, obj_vertices, write_obj
from test_cli_fields import ply_vertex_table

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def scene_of(page):
    """The scene JSON embedded in a page."""
    text = pathlib.Path(page).read_text()
    m = re.search(r'<script id="ifem-scene" type="application/json">(.*?)</script>', text, re.S)
    assert m, "no scene block"
    return json.loads(m.group(1))


def floats(b64):
    raw = base64.b64decode(b64)
    return struct.unpack(f"<{len(raw) // 4}f", raw)


def uints(b64):
    raw = base64.b64decode(b64)
    return struct.unpack(f"<{len(raw) // 4}I", raw)


def view(cli, *args):
    """`ifem view ARGS`, skipping when three.js is not installed."""
    r = cli.run("view", *args)
    if r.rc != 0 and "three.js not found" in r.err:
        pytest.skip("three.js is not installed: scripts/setup.sh (npm install three)")
    assert r.rc == 0, r.describe()
    return r


@pytest.fixture(scope="module")
def spot_outputs(tmp_path_factory):
    """Made once: spot's distance from vertex 0 as `ifem distance` writes it (.ply), and its
    vertices' heights y as a .txt of one value per vertex."""
    out = tmp_path_factory.mktemp("spot_outputs")
    exe, spot = os.environ["IFEM_EXE"], pathlib.Path(os.environ["IFEM_TEST_DATA"]) / "spot.obj"
    d = out / "d.ply"
    subprocess.run([exe, "distance", spot, "--source", "0", "-o", d, "--quiet"], check=True,
                   timeout=110)
    t = out / "height.txt"
    t.write_text("".join(f"{p[1]!r}\n" for p in obj_vertices(spot)))
    return d, t


def test_page_is_self_contained(cli, spot_outputs):
    d, t = spot_outputs
    page = cli.out / "spot.html"
    r = view(cli, cli.spot, "--field", f"{d},{t}", "--units", "m", "-o", page, "--quiet")
    assert "2930 vertices, 2 fields" in r.output, r.describe()
    html = page.read_text()
    assert not re.search(r"<script[^>]+src=|<link|@import|url\(http", html)
    imports = json.loads(re.search(r'<script type="importmap">(.*?)</script>', html, re.S).group(1))
    assert all(u.startswith("data:text/javascript;base64,") for u in imports["imports"].values())
    s = scene_of(page)
    xyz = floats(s["positions"])
    v = obj_vertices(cli.spot)
    assert len(xyz) == 3 * SPOT_VERTICES and s["vertices"] == SPOT_VERTICES
    assert max(abs(xyz[3 * i + k] - v[i][k]) for i in (0, 1000, 2929) for k in range(3)) < 1e-6
    assert len(uints(s["faces"])) == 3 * 5856
    names = [f["name"] for f in s["fields"]]
    assert names == ["d: distance", "height"], names
    values = numbers(t)
    f = s["fields"][1]
    assert f["min"] == min(values) and f["max"] == max(values)
    assert f["units"] == "m"
    scale = max(abs(x) for x in values)
    assert max(abs(a - b) for a, b in zip(floats(f["values"]), values)) <= 1e-6 * scale


# intrinsic edges: as many polylines as the refined triangulation has edges (spot is a sphere:
# E = 3V − 6); curves: the OBJ's polylines with their points
def test_intrinsic_edges_and_curves(cli):
    o = cli.out
    r = cli.ok("refine", cli.spot, "--save", o / "spot.ifem", "--quiet")
    refined = int(re.search(r"-> (\d+) refined", r.output).group(1))
    (o / "c.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1\nl 1 2 3\nl 3 4 1\n")
    page = o / "idt.html"
    r = view(cli, cli.spot, "--triangulation", o / "spot.ifem", "--curves", o / "c.obj",
             "-o", page, "--quiet")
    s = scene_of(page)
    counts = uints(s["intrinsic_edges"]["counts"])
    assert len(counts) == 3 * refined - 6 and refined > SPOT_VERTICES
    assert all(c >= 2 for c in counts)
    assert len(floats(s["intrinsic_edges"]["points"])) == 3 * sum(counts)
    assert f"{3 * refined - 6} intrinsic edges" in r.output
    assert [c["name"] for c in s["curves"]] == ["c"]
    assert uints(s["curves"][0]["lines"]["counts"]) == (3, 3)


def test_refusals(cli, tmp_path):
    o = cli.out
    out = o / "bad.html"
    cli.fails_no_partial("three.js not found .*npm install", out, "view", cli.spot,
                         "--three", o / "nowhere", "-o", out, "--quiet")
    # a triangulation of another mesh, a field of another mesh (view() skips without three.js)
    square = o / "square.obj"
    write_obj(square, [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [(1, 2, 3), (1, 3, 4)])
    cli.ok("refine", square, "--save", o / "fan.ifem", "--quiet")
    cli.ok("distance", square, "--source", 0, "-o", o / "fan.ply", "--quiet")
    view(cli, square, "-o", o / "fan.html", "--quiet")
    cli.fails_no_partial("another mesh", out, "view", cli.spot, "--triangulation",
                         o / "fan.ifem", "-o", out, "--quiet")
    cli.fails_no_partial("fan.ply: 4 vertices, the mesh has 2930", out, "view", cli.spot,
                         "--field", o / "fan.ply", "-o", out, "--quiet")
    cli.fails("symmetry", "view", cli.spot, "--symmetry", 7, "-o", out)
    cli.fails_no_partial("not an .obj polyline file", out, "view", cli.spot, "--curves",
                         o / "fan.ply", "-o", out, "--quiet")
    r = cli.ok("view", "--help")
    assert "--triangulation" in r.output and "examples:" in r.output


# a PLY mesh with its own vertex properties is coloured by them; a point cloud gets no faces
def test_mesh_properties_and_point_cloud(cli, spot_outputs):
    d, t = spot_outputs
    page = cli.out / "d.html"
    r = view(cli, d, "-o", page, "--quiet")
    assert "2930 vertices, 1 fields" in r.output, r.describe()
    assert [f["name"] for f in scene_of(page)["fields"]] == ["distance"]
    cloud = cli.spot_points()
    r = view(cli, cloud, "--field", t, "-o", cli.out / "cloud.html", "--quiet")
    assert "2930 points, 1 fields" in r.output, r.describe()
    s = scene_of(cli.out / "cloud.html")
    assert s["faces"] == "" and s["vertices"] == SPOT_VERTICES


def chromium_selftest(page, tmp_path):
    """Loads PAGE#selftest in headless Chromium with every network request refused; the JSON
    the page writes into #ifem-selftest."""
    profile = tmp_path / "chromium-profile"
    cmd = [CHROMIUM, "--headless", "--no-sandbox", f"--user-data-dir={profile}",
           "--no-first-run", "--disable-extensions", "--disable-background-networking",
           "--disable-component-update", "--disable-sync", "--disable-default-apps",
           "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--disable-gpu-compositing", "--in-process-gpu", "--disable-dev-shm-usage",
           "--window-size=600,500",
           "--proxy-server=http://127.0.0.1:9", "--host-resolver-rules=MAP * ~NOTFOUND",
           "--dump-dom", pathlib.Path(page).resolve().as_uri() + "#selftest"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=90)
    m = re.search(r'<pre id="ifem-selftest"[^>]*>(.*?)</pre>', proc.stdout, re.S)
    assert m and m.group(1), "no self-test output\n" + proc.stdout[-2000:] + proc.stderr[-2000:]
    return json.loads(m.group(1).replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">"))


@pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed")
def test_page_in_headless_chromium(cli, spot_outputs, tmp_path):
    d, t = spot_outputs
    page = cli.out / "spot.html"
    view(cli, cli.spot, "--field", f"{d},{t}", "--units", "m", "-o", page, "--quiet")
    r = chromium_selftest(page, tmp_path)
    # spot fills a good part of the window (its bounding sphere fits the view: 9% at 600×500)
    assert 0.03 < r["covered"] / r["pixels"] < 0.9, r
    # the legend shows the first property's exact range (the PLY's doubles) and the units
    distance = ply_vertex_table(d)["distance"]
    assert r["legend"]["name"] == "d: distance" and r["legend"]["visible"], r
    assert r["legend"]["min"] == min(distance) == 0.0, r
    assert r["legend"]["max"] == max(distance) > 1.0, r
    assert r["legend"]["units"] == "m"
    # the second field (the height) colours spot differently
    assert r["changed"] > 0.3 * r["covered"], r
    assert r["network"] == [], r
    assert r["fields"] == ["d: distance", "height"] and not r["cloud"]
