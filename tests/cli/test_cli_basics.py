"""`ifem` help, info and laplacian; the error paths every command shares (one line on stderr,
non-zero exit, no partial output); degenerate geometry refused by every command.

The output checks are re.search(..., re.S) on stdout + stderr, as ctest's
PASS_REGULAR_EXPRESSION was (its "." matches a newline too)."""

import json
import re
import shutil

from clitools import SPOT_VERTICES, count_lines, lines, numbers


def test_help(cli):
    r = cli.ok("--help")
    assert re.search("laplacian", r.output, re.S), r.describe()


def test_info(cli):
    r = cli.ok("info", cli.spot, "--quiet")
    assert re.search("vertices 2930 .*genus 0", r.output, re.S), r.describe()


def test_info_json(cli):
    r = cli.ok("info", cli.spot, "--json", "--quiet")
    assert re.search('"vertices": 2930', r.output, re.S), r.describe()


def test_laplacian(cli):
    r = cli.ok("laplacian", cli.spot, "-o", cli.out / "spot", "--quiet")
    assert re.search("2930×2930.*all weights non-negative", r.output, re.S), r.describe()


def test_laplacian_help(cli):
    r = cli.ok("laplacian", "--help")
    assert re.search("positive semi-definite", r.output, re.S), r.describe()


def test_missing_file(cli):
    cli.fails("does_not_exist.obj", "info", cli.out / "does_not_exist.obj")


def test_unknown_option(cli):
    cli.fails("unknown option --frobnicate", "info", cli.spot, "--frobnicate")


def test_unknown_command(cli):
    cli.fails("unknown command", "frobnicate")


def test_laplacian_needs_output(cli):
    cli.fails("missing -o", "laplacian", cli.spot)


# info: the path taken for a nonmanifold mesh and for a point cloud (made from spot's vertices)
def test_info_tufted(cli):
    r = cli.ok("info", cli.fan3, "--quiet")
    assert re.search("path: tufted", r.output, re.S), r.describe()


def test_info_pointcloud(cli):
    r = cli.ok("info", cli.spot_points(), "--quiet")
    assert re.search("path: pointcloud", r.output, re.S), r.describe()


# `ifem info --json` is valid JSON whatever the path holds: quotes, backslashes, control
# characters, non-ASCII, a byte that is not UTF-8 (mesh and point-cloud variants)
def test_info_json_paths(cli):
    folder = cli.out / 'json "paths"'
    folder.mkdir()
    points = cli.spot_points()
    names = ['q"uote', "back\\slash", "naïve €", "tab\tand\nnewline",
             "bad" + b"\xff".decode("utf-8", "surrogateescape") + "byte", "ctl\x01"]
    for name in names:
        for ext in ("obj", "xyz"):
            path = folder / f"{name}.{ext}"
            shutil.copyfile(cli.spot if ext == "obj" else points, path)
            r = cli.ok("info", path, "--json", "--quiet")
            d = json.loads(r.stdout_bytes.decode("utf-8"))  # strict: the output must be UTF-8
            assert d["file"] == str(path) or "\ufffd" in d["file"], (d["file"], r.describe())
            assert d.get("vertices", d.get("points")) == SPOT_VERTICES, d


# Scale-free geometry (issue 10): spot scaled by 1e300 gives the same distances times 1e300;
# its mass cannot be represented, so `laplacian` refuses it (exit 1, no partial output) instead
# of writing inf; all vertices at one point is one clear error from every command.
def test_scale_free(cli):
    huge = cli.out / "spot_huge.obj"
    point = cli.out / "spot_point.obj"
    with open(huge, "w") as fh, open(point, "w") as fp:
        for line in lines(cli.spot):
            if line.startswith("v "):
                x, y, z = (float(t) for t in line.split()[1:4])
                fh.write(f"v {x * 1e300:.17g} {y * 1e300:.17g} {z * 1e300:.17g}\n")
                fp.write("v 1 2 3\n")
            else:
                fh.write(line + "\n")
                fp.write(line + "\n")
    cli.ok("distance", cli.spot, "--source", 0, "-o", cli.out / "d_unit.txt", "--quiet")
    cli.ok("distance", huge, "--source", 0, "-o", cli.out / "d_huge.txt", "--quiet")
    unit = numbers(cli.out / "d_unit.txt")
    scaled = numbers(cli.out / "d_huge.txt")
    assert len(unit) == len(scaled) == SPOT_VERTICES
    deviation = max(abs(b / 1e300 / a - 1) for a, b in zip(unit[1:], scaled[1:]))
    assert deviation < 1e-9, f"max relative deviation {deviation}"

    r = cli.run("laplacian", huge, "-o", cli.out / "huge", "--quiet")
    assert r.rc != 0, r.describe()
    assert re.search("not representable in double precision", r.err), r.describe()
    assert not (cli.out / "huge_L.mtx").exists()
    assert not (cli.out / "huge_M.mtx").exists()

    o = cli.out
    for cmd in (["info"], ["laplacian", "-o", o / "pt"], ["distance", "--source", 0, "-o",
                o / "pt.txt"], ["eigen", "-k", 3, "-o", o / "pt.ply"], ["poisson", "-o",
                o / "pt.txt"], ["refine", "-o", o / "pt_cs.ply"],
                ["geodesic", "--path", "0,1", "-o", o / "pt.obj"]):
        r = cli.run(*cmd, point, "--quiet")
        assert r.rc != 0, "accepted: " + r.describe()
        assert re.search("no surface to compute on", r.err), r.describe()
    assert count_lines(cli.out / "d_unit.txt") == SPOT_VERTICES
