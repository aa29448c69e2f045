"""Curves at the edges of what they can do (issue 30): a triangle soup with curves computes at
the default settings; a Bézier curve finer than the mesh or over --memory-budget is refused up
front with its figures (and the rounds that fit complete); FlipOut's iteration cap is an error
unless --accept-partial; file errors name FILE:line and show garbage bytes escaped on one line;
an empty constraints file and two different directions at one vertex are refused.
tests/data/soup_icosphere.obj: 8 icosphere pieces with their own vertices (piece 0: vertices
0..~30), a lone triangle (240..242) and a zero-area face (243..245)."""

import math
import re

from clitools import SPOT_VERTICES, lines, numbers

SOUP_VERTICES = 246


def test_soup_curves_at_defaults(cli):
    soup, c = cli.data / "soup_icosphere.obj", cli.out / "soup_c.txt"
    # curves on one piece: a path along its boundary (0 -> 1 passes a reflex corner) and one
    # through three vertices; the distance is 0 on them, finite on their piece, inf elsewhere
    c.write_text("0 0 1\n1 5 8 13\n")
    for extra in ([], ["--mollify", "1e-6"], ["--mollify", "1e-3"], ["--refine"]):
        d = cli.out / "soup_d.txt"
        cli.ok("distance", soup, "--curves", c, "-o", d, "--quiet", *extra)
        v = numbers(d)
        assert len(v) == SOUP_VERTICES
        for i in (0, 1, 5, 8, 13):
            assert v[i] == 0, (extra, i, v[i])
        finite = [x for x in v if math.isfinite(x)]
        assert 20 <= len(finite) <= 40, (extra, len(finite))  # piece 0 only
        assert all(0 <= x < 2.0 for x in finite)  # within a piece of the unit sphere
        assert sum(1 for x in v[240:] if math.isinf(x)) == 6  # the lone and the flat piece
    u = cli.out / "soup_u.txt"
    cli.ok("poisson", soup, "--curves", c, "-o", u, "--quiet")
    assert all(-1e-12 <= x <= 1 + 1e-12 for x in numbers(u))
    # a curve on the zero-area piece itself: 0 there, every other piece unreachable
    (cli.out / "flat_c.txt").write_text("0 243 244\n")
    cli.ok("distance", soup, "--curves", cli.out / "flat_c.txt", "-o", d, "--quiet")
    v = numbers(d)
    assert sum(1 for x in v if math.isinf(x)) == SOUP_VERTICES - 3


def test_bezier_refused_up_front_or_completes(cli):
    o, spot = cli.out, cli.spot
    bz = o / "bz.txt"
    bz.write_text("bezier=16 0 1 : 0 500 1000 1500\n")
    r = cli.refuse(1, r"bz.txt:1: a Bézier curve of degree 3 with 16 rounds adds up to "
                      r"3\.93e\+05 vertices, .*Use at most 8 rounds$", o / "bz_d.txt",
                   "distance", spot, "--curves", bz)
    assert "intrinsic" not in r.err and not re.search(r"edge \d", r.err), r.err
    cli.refuse(1, "Use at most 8 rounds", o / "bz.obj", "geodesic", spot, "--path",
               "0,500,1000,1500", "--bezier", 16)
    bz.write_text("bezier=8 0 1 : 0 500 1000 1500\n")  # the most that fit: it completes
    d = o / "bz_d.txt"
    cli.ok("distance", spot, "--curves", bz, "-o", d, "--quiet")
    assert len(numbers(d)) == SPOT_VERTICES
    bz.write_text("bezier=4 0 1 : 0 500 1000 1500\n")
    cli.refuse(1, r"about 0\.0124 GB at 4 KiB per vertex, above the memory budget of 0\.001 GB",
               o / "bz_d.txt", "distance", spot, "--curves", bz, "--memory-budget", 0.001)


def test_iteration_cap_is_an_error_unless_accepted(cli):
    o, spot = cli.out, cli.spot
    net = o / "net.txt"
    net.write_text("path 0 500 1000\npath 10 700 1400\nloop 20 900 1800\n")
    cli.refuse(1, r"FlipOut stopped at its iteration cap \(3 reroutes.*not a geodesic network.*"
                  r"--accept-partial", o / "net.obj", "geodesic", spot, "--network", net,
               "--max-iterations", 3)
    r = cli.ok("geodesic", spot, "--network", net, "--max-iterations", 3, "--accept-partial",
               "-o", o / "net.obj", "--quiet")
    assert "stopped: iteration cap" in r.out
    r = cli.ok("geodesic", spot, "--network", net, "-o", o / "net.obj", "--quiet")
    assert "stopped: iteration cap" not in r.out, r.out  # the default cap: it finishes
    cli.refuse(2, "--accept-partial accepts curves of --curves FILE", o / "d.txt", "distance",
               spot, "--source", 0, "--accept-partial")
    # the same cap on a curves file (poisson/distance/field --curves --max-iterations)
    curves = o / "cap_curves.txt"
    curves.write_text("0 1 : 0 1500\n")
    cli.refuse(1, r"FlipOut stopped at its iteration cap \(3 reroutes.*--accept-partial",
               o / "cap_u.txt", "poisson", spot, "--curves", curves, "--max-iterations", 3)
    r = cli.ok("poisson", spot, "--curves", curves, "--max-iterations", 3, "--accept-partial",
               "-o", o / "cap_u.txt", "--quiet")
    assert len(numbers(o / "cap_u.txt")) == SPOT_VERTICES
    cli.ok("distance", spot, "--curves", curves, "-o", o / "cap_d.txt", "--quiet")
    cli.refuse(2, "--max-iterations caps FlipOut on the curves of --curves FILE", o / "d.txt",
               "distance", spot, "--source", 0, "--max-iterations", 3)


def test_garbage_in_files_is_escaped_on_one_line(cli):
    o, spot = cli.out, cli.spot
    junk = b"\x00\x01\x1b[31mRED\rX\x7f\xff\xfe\n"
    (o / "g_curves.txt").write_bytes(b"0 1 " + junk)
    (o / "g_net.txt").write_bytes(b"path 0 " + junk)
    (o / "g_con.txt").write_bytes(b"1 " + junk)
    (o / "g_long.txt").write_bytes(b"0 1 2 " + b"\x80" * 5000 + b"\n")
    runs = [
        ("g_curves.txt:1: '\\\\0\\\\x01\\\\x1b\\[31mRED' is not a vertex id", "distance",
         "--curves", o / "g_curves.txt", "d.txt"),
        ("g_net.txt:1: '\\\\0\\\\x01\\\\x1b\\[31mRED' is not a point", "geodesic", "--network",
         o / "g_net.txt", "g.obj"),
        ("g_con.txt:1: expected 'VERTEX X Y Z'.*got '1 \\\\0\\\\x01", "field", "--constraints",
         o / "g_con.txt", "f.txt"),
        (r"g_long.txt:1: '(\\x80){40}'\.\.\. \(5000 bytes\) is not a vertex id", "distance",
         "--curves", o / "g_long.txt", "d.txt"),
    ]
    for regex, command, opt, path, out in runs:
        r = cli.refuse(1, regex, o / out, command, spot, opt, path)
        assert all(32 <= ord(ch) or ch == "\n" for ch in r.err), r.err
        assert "\x7f" not in r.err and "\ufffd" not in r.err, r.err


def test_constraints_file_errors_name_their_lines(cli):
    o, spot = cli.out, cli.spot
    (o / "c_empty.txt").write_text("# nothing here\n\n")
    cli.refuse(1, "c_empty.txt: no direction in the file", o / "f.txt", "field", spot,
               "--constraints", o / "c_empty.txt")
    (o / "c_range.txt").write_text("1 1 0 0\n# the next is out of range\n2930 1 0 0\n")
    cli.refuse(1, r"c_range.txt:3 \(vertex 2930\): vertex out of range \[0, 2930\)", o / "f.txt",
               "field", spot, "--constraints", o / "c_range.txt")
    (o / "c_conflict.txt").write_text("5 1 0 0\n7 0 1 0\n5 0 1 0\n")
    cli.refuse(1, r"c_conflict.txt:3 \(vertex 5\): a second, different direction at the vertex "
                  r"of .*c_conflict.txt:1 \(vertex 5\)", o / "f.txt", "field", spot,
               "--constraints", o / "c_conflict.txt")
    (o / "c_same.txt").write_text("5 1 0 0\n5 2 0 0\n")  # the same direction twice: fine
    f = o / "f.txt"
    cli.ok("field", spot, "--constraints", o / "c_same.txt", "-o", f, "--quiet")
    assert len(lines(f)) == SPOT_VERTICES
