"""Progress bars of long commands: drawn on stderr only when stderr is a terminal (a pseudo-
terminal here, Python's pty module), never in a pipe, never with --quiet, never on stdout;
not before the delay (2 s; IFEM_PROGRESS_DELAY lowers it so that these quick runs draw);
throttled to ≤ 10 draws per second; erased at the end."""

import os
import pty
import re
import subprocess
import time

import pytest

DRAW = re.compile(rb"\r\x1b\[Kifem: ([a-z -]+) \[([#.]{30})\] +(\d+)%")
ERASE = b"\r\x1b[K"


def run_tty(cli, args, delay="0", tty=True):
    """Runs `ifem ARGS` with stderr on a pseudo-terminal (or a pipe when tty is False) and
    stdout on a pipe; returns (exit code, stdout bytes, stderr bytes, seconds)."""
    env = dict(os.environ, IFEM_PROGRESS_DELAY=delay)
    start = time.monotonic()
    if not tty:
        p = subprocess.run([str(cli.exe), *map(str, args)], cwd=cli.out, env=env,
                           capture_output=True, timeout=110)
        return p.returncode, p.stdout, p.stderr, time.monotonic() - start
    master, slave = pty.openpty()
    try:
        proc = subprocess.Popen([str(cli.exe), *map(str, args)], cwd=cli.out, env=env,
                                stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=slave)
    finally:
        os.close(slave)
    err = []
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:  # EIO: the child closed the terminal's last handle
            break
        if not chunk:
            break
        err.append(chunk)
    os.close(master)
    out = proc.stdout.read()
    proc.stdout.close()
    rc = proc.wait(timeout=110)
    return rc, out, b"".join(err), time.monotonic() - start


def draws(err):
    return [(m.group(1).decode(), int(m.group(3))) for m in DRAW.finditer(err)]


# (arguments, the long stage it must show)
COMMANDS = [
    (["refine", "{spot}", "--resolution", "0.5", "-o", "r.ply"], "refine"),
    (["eigen", "{spot}", "-k", "8", "-o", "e.ply"], "eigenpairs"),
    (["distance", "{spot}", "--sources-batch", "batch.txt", "-o", "d.npy"], "heat distances"),
    (["geodesic", "{spot}", "--all-from", "0", "-o", "g.txt"], "single-source geodesics"),
]


def command(cli, args):
    (cli.out / "batch.txt").write_text("".join(f"{7 * i}\n" for i in range(100)))
    return [a.format(spot=cli.spot) for a in args]


@pytest.mark.parametrize("args,stage", COMMANDS, ids=[c[1] for c in COMMANDS])
def test_bar_on_a_terminal(cli, args, stage):
    rc, out, err, _ = run_tty(cli, command(cli, args))
    assert rc == 0, err.decode("utf-8", "replace")
    seen = draws(err)
    assert stage in {s for s, _ in seen}, err
    for s, percent in seen:
        assert 0 <= percent < 100, (s, percent)
    # erased at the end: after the last draw comes an erase, and no bar is left on screen
    assert err.rfind(ERASE) > err.rfind(b"ifem: " + stage.encode() + b" ["), err
    # stdout is the results' alone
    assert b"\x1b" not in out and b"\r" not in out and b"[#" not in out and b"[." not in out


@pytest.mark.parametrize("args,stage", COMMANDS[1:3], ids=[c[1] for c in COMMANDS[1:3]])
def test_no_bar_in_a_pipe_or_with_quiet(cli, args, stage):
    args = command(cli, args)
    rc, out, err, _ = run_tty(cli, args, tty=False)
    assert rc == 0, err
    assert b"\x1b" not in err and not draws(err), err
    assert b"ifem: read" in err  # the progress lines stay
    rc, out, err, _ = run_tty(cli, [*args, "--quiet"])
    assert rc == 0, err
    assert err == b"", err  # --quiet: nothing at all on the terminal


def test_no_bar_before_the_delay(cli):
    # a command of well under 2 s on a terminal, with the default delay: lines, no bar
    rc, _, err, seconds = run_tty(cli, ["info", cli.spot], delay="")
    assert rc == 0, err
    assert seconds < 2.0 or pytest.skip(f"the machine is too slow for this check ({seconds} s)")
    assert not draws(err) and b"\x1b" not in err, err


def test_draws_are_throttled(cli):
    args = ["refine", cli.spot, "--resolution", "0.5", "-o", "r.ply"]
    rc, _, err, seconds = run_tty(cli, args)
    assert rc == 0, err
    seen = draws(err)
    stages = {s for s, _ in seen}
    # at most 10 per second, plus the first draw of each stage
    assert len(seen) <= 10 * seconds + len(stages) + 1, (len(seen), seconds, stages)
