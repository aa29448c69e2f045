"""Checks shared by the CLI tests (conftest.py makes the fixtures from them)."""

import pathlib
import re
import subprocess

SPOT_VERTICES = 2930
SPOT_FACES = 5856


class Result:
    """One finished `ifem` run: exit code, stdout and stderr (decoded, never raising)."""

    def __init__(self, args, proc):
        self.args = args
        self.rc = proc.returncode
        self.stdout_bytes = proc.stdout
        self.out = proc.stdout.decode("utf-8", "replace")
        self.err = proc.stderr.decode("utf-8", "replace")

    @property
    def output(self):
        return self.out + self.err

    def describe(self):
        return (f"`ifem {' '.join(map(str, self.args))}` exited {self.rc}\n"
                f"--- stdout ---\n{self.out}--- stderr ---\n{self.err}")

    def last_err_line(self):
        lines = self.err.rstrip("\n").split("\n")
        return lines[-1]


def grep(pattern, text):
    """True when a line of `text` matches the regex `pattern` (grep -q / grep -E -q)."""
    rx = re.compile(pattern)
    return any(rx.search(line) for line in text.split("\n"))


def head_bytes(path, n):
    """The first n bytes of a (possibly binary) file as text, for header checks."""
    with open(path, "rb") as f:
        return f.read(n).decode("latin-1")


def lines(path):
    """The file's lines without their newline ("wc -l" counts newlines: see count_lines)."""
    return pathlib.Path(path).read_text(encoding="utf-8", errors="replace").splitlines()


def count_lines(path):
    """Like `wc -l`: the number of newline characters."""
    return pathlib.Path(path).read_bytes().count(b"\n")


def numbers(path, column=0):
    """The `column`-th number of every line (a float; a line that is not a number fails)."""
    out = []
    for i, line in enumerate(lines(path)):
        fields = line.split()
        assert len(fields) > column, f"{path}:{i + 1}: no column {column}: {line!r}"
        out.append(float(fields[column]))
    return out


def close(a, b, rel=1e-6):
    """|a − b| ≤ rel · max(|a|, |b|, 1e-300)."""
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


def same_point(p, q, tol=1e-6):
    """Two 3D points within tol (traces end at their vertex up to flip_geodesic.h's round-off)."""
    assert len(p) == 3 and len(q) == 3, (p, q)
    d = sum((a - b) ** 2 for a, b in zip(p, q)) ** 0.5
    return d <= tol


def obj_vertices(path):
    """The positions of an OBJ's `v` lines."""
    return [tuple(float(x) for x in line.split()[1:4]) for line in lines(path)
            if line.startswith("v ")]


def obj_faces(path):
    """The faces of an OBJ as 1-based vertex indices (the `v/vt/vn` suffixes dropped)."""
    return [tuple(int(tok.split("/")[0]) for tok in line.split()[1:]) for line in lines(path)
            if line.startswith("f ")]


def write_obj(path, vertices, faces):
    """An OBJ with full-precision positions and 1-based faces."""
    with open(path, "w") as f:
        for v in vertices:
            f.write("v " + " ".join(f"{x:.17g}" for x in v) + "\n")
        for t in faces:
            f.write("f " + " ".join(str(i) for i in t) + "\n")


class Cli:
    """Runs `ifem` in a fresh directory (`self.out`, the test's tmp_path)."""

    def __init__(self, exe, data, out):
        self.exe = exe
        self.data = data
        self.out = out
        self.spot = data / "spot.obj"
        self.fan3 = data / "fan3.obj"

    def run(self, *args, stdin=None):
        args = [str(a) for a in args]
        proc = subprocess.run([str(self.exe), *args], cwd=self.out, capture_output=True,
                              input=stdin.encode() if stdin is not None else None, timeout=110)
        return Result(args, proc)

    def ok(self, *args):
        """Runs and requires exit 0."""
        r = self.run(*args)
        assert r.rc == 0, r.describe()
        return r

    def fails(self, regex, *args, rc=None):
        """scripts/expect_fail.sh: a non-zero exit (exactly `rc` when given) whose last stderr
        line matches the extended regex `regex`."""
        r = self.run(*args)
        assert r.rc != 0, "expected a failure, got exit 0\n" + r.describe()
        if rc is not None:
            assert r.rc == rc, f"expected exit {rc}\n" + r.describe()
        assert re.search(regex, r.last_err_line()), \
            f"last stderr line does not match {regex!r}\n" + r.describe()
        return r

    def fails_no_partial(self, regex, output, *args, rc=None):
        """fails(), and neither `output` nor `output.tmp` exists afterwards (removed first)."""
        output = pathlib.Path(output)
        tmp = pathlib.Path(str(output) + ".tmp")
        for p in (output, tmp):
            p.unlink(missing_ok=True)
        r = self.fails(regex, *args, rc=rc)
        assert not output.exists(), f"partial output left behind: {output}"
        assert not tmp.exists(), f"partial output left behind: {tmp}"
        return r

    def refuse(self, rc, regex, output, *args):
        """`ifem ARGS -o OUTPUT --quiet` exits exactly `rc` with exactly one stderr line that
        matches `regex`, and leaves neither OUTPUT nor OUTPUT.tmp."""
        output = pathlib.Path(output)
        tmp = pathlib.Path(str(output) + ".tmp")
        for p in (output, tmp):
            p.unlink(missing_ok=True)
        r = self.run(*args, "-o", output, "--quiet")
        assert r.rc == rc, f"expected exit {rc}\n" + r.describe()
        assert r.err.count("\n") == 1, "expected one stderr line\n" + r.describe()
        assert re.search(regex, r.err), f"stderr does not match {regex!r}\n" + r.describe()
        assert not output.exists(), f"partial output left behind: {output}"
        assert not tmp.exists(), f"partial output left behind: {tmp}"
        return r

    def spot_points(self, name="spot_points.xyz"):
        """spot's vertices as a point cloud (.xyz), in the output directory."""
        path = self.out / name
        with open(path, "w") as f:
            for line in lines(self.spot):
                if line.startswith("v "):
                    f.write(" ".join(line.split(" ")[1:4]) + "\n")
        return path


def face_components(n_vertices, faces):
    """The connected piece of each vertex (0-based ids; a label per vertex, equal labels = one
    piece), joining the corners of every face (union-find); a vertex in no face is its own."""
    parent = list(range(n_vertices))

    def find(v):
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    for face in faces:
        for u in face[1:]:
            parent[find(u)] = find(face[0])
    return [find(v) for v in range(n_vertices)]
