#!/usr/bin/env python3
"""`ifem distance --exact` against every exact reference of ../shared/data/reference (CGAL's
exact code, MANIFEST.md): per file the max relative difference over reachable vertices, the
windows and the wall time. Usage: scripts/exact_vs_references.py IFEM [SHARED_DATA] [--skip STEM]"""

import math
import pathlib
import re
import subprocess
import sys
import tempfile
import time


def main():
    ifem = sys.argv[1]
    shared = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("--")
                          else pathlib.Path(__file__).resolve().parents[2] / "shared" / "data")
    skip = set(sys.argv[sys.argv.index("--skip") + 1].split(",")) if "--skip" in sys.argv else set()
    worst_all = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "d.txt"
        for ref in sorted((shared / "reference").glob("*.exact.txt")):
            stem, src = ref.name[:-len(".exact.txt")].rsplit(".src", 1)
            if stem in skip:
                continue
            mesh = next((shared / "meshes").glob(stem + ".*"))
            t = time.time()
            r = subprocess.run([ifem, "distance", str(mesh), "--source", src, "--exact", "-o",
                                str(out)], capture_output=True, text=True)
            seconds = time.time() - t
            if r.returncode != 0:
                print(f"{ref.name}: failed: {r.stderr.strip().splitlines()[-1]}")
                continue
            windows = re.search(r"exact distance: (\d+) windows", r.stderr).group(1)
            path = re.search(r"path: (\w+)", r.stderr).group(1)
            d = [float(x) for x in out.read_text().split()]
            e = [float(x) for x in ref.read_text().split()]
            rel = [(a - b) / b for a, b in zip(d, e) if math.isfinite(b) and b > 0]
            worst = max(abs(x) for x in rel)
            below = max(-x for x in rel)
            print(f"{ref.name:40s} {path:9s} windows {windows:>10s} {seconds:7.2f} s  "
                  f"max |rel| {worst:.2e}  max (ref-ifem)/ref {below:.2e}")
            if stem != "conrod":
                worst_all = max(worst_all, worst)
    print(f"max |rel| over the edge-manifold references: {worst_all:.2e}")


if __name__ == "__main__":
    main()
