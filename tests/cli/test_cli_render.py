"""`ifem render`: the PNG read back (size, pixels) on a unit sphere coloured by height (the
projected disc's area, the colour map's order, one isoline band per level), a distance field
on spot from a PLY or through --field (the same bytes), curves drawn (OBJ polylines, the
intrinsic edges of `ifem refine --lines`), the same bytes twice, and the refusals (bad size, view, property, isolines without a field) with no partial file."""

import math
import struct
import zlib

from clitools import grep


def read_png(path):
    """(width, height, rows): rows[y][x] = (r, g, b), for the 8-bit RGB, filter-0 PNGs ifem
    writes (every chunk's CRC checked)."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, width = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        assert struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])[0] == zlib.crc32(kind + body)
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert (depth, colour) == (8, 2), "8-bit RGB"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = 1 + 3 * width
    assert len(raw) == stride * height
    rows = []
    for y in range(height):
        assert raw[y * stride] == 0, "filter type 0"
        line = raw[y * stride + 1:(y + 1) * stride]
        rows.append([tuple(line[3 * x:3 * x + 3]) for x in range(width)])
    return width, height, rows


def write_sphere_ply(path, n_lat=48, n_lon=96):
    """A unit UV sphere as an ASCII PLY with its height as the vertex property `height`."""
    verts = [(0.0, 1.0, 0.0)]
    for i in range(1, n_lat):
        theta = math.pi * i / n_lat
        for j in range(n_lon):
            phi = 2 * math.pi * j / n_lon
            verts.append((math.sin(theta) * math.sin(phi), math.cos(theta),
                          math.sin(theta) * math.cos(phi)))
    verts.append((0.0, -1.0, 0.0))
    ring = lambda i, j: 1 + (i - 1) * n_lon + j % n_lon  # noqa: E731
    faces = [(0, ring(1, j), ring(1, j + 1)) for j in range(n_lon)]
    for i in range(1, n_lat - 1):
        for j in range(n_lon):
            faces += [(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)),
                      (ring(i, j), ring(i + 1, j + 1), ring(i, j + 1))]
    last = len(verts) - 1
    faces += [(last, ring(n_lat - 1, j + 1), ring(n_lat - 1, j)) for j in range(n_lon)]
    with open(path, "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(verts)}\nproperty double x\n"
                f"property double y\nproperty double z\nproperty double height\n"
                f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in verts:
            f.write(f"{v[0]!r} {v[1]!r} {v[2]!r} {v[1]!r}\n")
        for t in faces:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")
    return path


WHITE = (255, 255, 255)


# The unit sphere seen from +z fills a disc of radius 0.9·min(W, H)/2 (the default fill); the
# top half has viridis's upper colours (less blue), the bottom half its lower ones.
def test_sphere_disc_and_colour_order(cli):
    sphere = write_sphere_ply(cli.out / "sphere.ply")
    r = cli.ok("render", sphere, "--size", "240x200", "--supersample", 1, "-o",
               cli.out / "s.png", "--quiet")
    assert grep(r"colour: height in \[-1, 1\]", r.out), r.describe()
    w, h, rows = read_png(cli.out / "s.png")
    assert (w, h) == (240, 200)
    disc = sum(p != WHITE for row in rows for p in row)
    radius = 0.9 * 100
    inner = radius * math.cos(math.pi / 48) - 1  # the UV sphere's silhouette, less a pixel
    assert math.pi * inner ** 2 <= disc <= math.pi * (radius + 1) ** 2, disc

    def blue_share(y0, y1):
        shares = [p[2] / sum(p) for row in rows[y0:y1] for p in row if p != WHITE and sum(p)]
        return sum(shares) / len(shares)
    assert blue_share(0, h // 2) < 0.35 < blue_share(h // 2, h)


# --isolines N: N dark bands down the middle column, at rows H/2 − r·(−1 + 2k/(N+1))
def test_isolines_bands(cli):
    sphere = write_sphere_ply(cli.out / "sphere.ply")
    cli.ok("render", sphere, "--size", "200x200", "--supersample", 1, "-o", cli.out / "p.png",
           "--quiet")
    _, _, plain = read_png(cli.out / "p.png")
    for n in (2, 5):
        cli.ok("render", sphere, "--size", "200x200", "--supersample", 1, "--isolines", n,
               "-o", cli.out / "i.png", "--quiet")
        _, _, lines = read_png(cli.out / "i.png")
        changed = [y for y in range(200) if lines[y][100] != plain[y][100]]
        bands = [y for y in changed if y - 1 not in changed]
        assert len(bands) == n, changed
        expected = [100 - 90 * (-1 + 2 * k / (n + 1)) for k in range(1, n + 1)]
        for y, row in zip(sorted(bands), sorted(expected)):
            assert abs(y - row) <= 2, (bands, expected)


# spot's distance: from its own PLY and through --field on the OBJ give the same bytes (same
# vertices, same property), twice; curves from `ifem geodesic` add red pixels
def test_distance_field_curves_and_determinism(cli):
    o = cli.out
    r = cli.ok("distance", cli.spot, "--source", 0, "-o", o / "d.ply", "--quiet")
    top = float(r.out.split("max distance ")[1].split(",")[0])
    r = cli.ok("render", o / "d.ply", "--size", "160x120", "-o", o / "a.png", "--quiet")
    lo, hi = (float(t) for t in r.out.split("in [")[1].split("]")[0].split(","))
    assert lo == 0 and abs(hi - top) <= 1e-5 * top, r.describe()
    cli.ok("render", cli.spot, "--field", o / "d.ply", "--property", "distance", "--size",
           "160x120", "-o", o / "b.png", "--quiet")
    assert (o / "a.png").read_bytes() == (o / "b.png").read_bytes()
    cli.ok("render", o / "d.ply", "--size", "160x120", "-o", o / "a2.png", "--quiet")
    assert (o / "a.png").read_bytes() == (o / "a2.png").read_bytes()
    cli.ok("geodesic", cli.spot, "--path", "0,1200", "-o", o / "path.obj", "--quiet")
    cli.ok("render", cli.spot, "--curves", o / "path.obj", "--view", "left", "--size", "160x120",
           "--wireframe", "-o", o / "c.png", "--quiet")
    cli.ok("render", cli.spot, "--curves", o / "path.obj", "--view", "right", "--size",
           "160x120", "-o", o / "c2.png", "--quiet")
    red = 0
    for name in ("c.png", "c2.png"):
        _, _, rows = read_png(o / name)
        red += sum(p[0] > 150 and p[1] < 100 and p[2] < 100 for row in rows for p in row)
    assert red > 10, "the geodesic shows from one side or the other"


# the intrinsic triangulation over the input (the thesis's figures): `ifem refine --lines`
# (binary or --ascii) drawn with --curves over --wireframe; the two files give the same bytes
def test_intrinsic_edges_over_the_input(cli):
    o = cli.out
    cli.ok("refine", cli.spot, "--lines", o / "e.ply", "--quiet")
    cli.ok("refine", cli.spot, "--lines", o / "ea.ply", "--ascii", "--quiet")
    for name in ("e", "ea"):
        cli.ok("render", cli.spot, "--wireframe", "--curves", o / f"{name}.ply", "--curve-width",
               1, "--size", "160x120", "-o", o / f"{name}.png", "--quiet")
    assert (o / "e.png").read_bytes() == (o / "ea.png").read_bytes()
    _, _, rows = read_png(o / "e.png")
    red = sum(p[0] > 150 and p[1] < 100 and p[2] < 100 for row in rows for p in row)
    assert red > 1000, red


def blue(rows):
    """Pixels of the intrinsic edges' colour (blue well above red and green)."""
    return sum(p[2] > p[0] + 60 and p[2] > p[1] + 30 for row in rows for p in row)


# --triangulation draws what `ifem view --triangulation` shows: the saved triangulation's edges
# traced over the input, in blue (on a grey colour map, so nothing else is blue); flips only (no insertion) draw fewer than flips + refinement,
# and a triangulation of another mesh is refused
def test_triangulation_as_ifem_view_draws_it(cli):
    o = cli.out
    sphere = write_sphere_ply(o / "sphere.ply", 10, 20)
    cli.ok("refine", sphere, "--max-insertions", 0, "--save", o / "flip.ifem", "--quiet")
    cli.ok("refine", sphere, "--resolution", 0.5, "--save", o / "ref.ifem", "--quiet")
    counts = []
    for name in ("flip", "ref"):
        r = cli.ok("render", sphere, "--triangulation", o / f"{name}.ifem", "--size", "320x240",
                   "--colormap", "gray", "-o", o / f"{name}.png", "--quiet")
        assert grep(r"wrote .*\(320x240\)", r.out), r.describe()
        counts.append(blue(read_png(o / f"{name}.png")[2]))
    cli.ok("render", sphere, "--size", "320x240", "--colormap", "gray", "-o", o / "none.png",
           "--quiet")
    assert blue(read_png(o / "none.png")[2]) == 0
    assert 1000 < counts[0] and counts[0] * 1.1 < counts[1], counts
    cli.refuse(1, r"triangulation|vertices", o / "x.png", "render", cli.spot, "--triangulation",
               o / "flip.ifem")


def test_refusals(cli):
    o = cli.out
    png = o / "x.png"
    cli.refuse(2, r"--size: expected WIDTHxHEIGHT", png, "render", cli.spot, "--size", "0x10")
    cli.refuse(2, r"--size: expected WIDTHxHEIGHT", png, "render", cli.spot, "--size", "640")
    cli.refuse(2, r"unknown view 'side' \(front, back, left, right, top, bottom\)", png,
               "render", cli.spot, "--view", "side")
    cli.refuse(2, r"unknown colour map 'jet'", png, "render", cli.spot, "--colormap", "jet")
    cli.refuse(2, r"colour range needs lo < hi", png, "render", cli.spot, "--min", 1, "--max", 0)
    cli.refuse(1, r"isolines need a field", png, "render", cli.spot, "--isolines", 3)
    cli.refuse(1, r"a legend needs a field", png, "render", cli.spot, "--legend")
    cli.refuse(1, r"no per-vertex property", png, "render", cli.spot, "--property", "height")
    sphere = write_sphere_ply(o / "sphere.ply", 6, 8)
    cli.refuse(1, r"no per-vertex property 'nope' \(the input has: height\)", png, "render",
               sphere, "--property", "nope")
    cli.refuse(1, r"has 42 vertices, .*spot.obj has 2930", png, "render", cli.spot, "--field",
               sphere)
    cli.refuse(2, r"\.png", o / "x.jpg", "render", cli.spot)
    cli.refuse(2, r"--curves", png, "render", cli.spot, "--curves", o / "c.txt")
    (o / "bad.ply").write_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\n"
                               "property double y\nproperty double z\nend_header\n0 0 0\n")
    cli.refuse(1, r"needs 'vertex' and 'edge' elements", png, "render", cli.spot, "--curves",
               o / "bad.ply")
