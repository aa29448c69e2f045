#!/usr/bin/env bash
# Installs a build tree into a temporary prefix and imports the installed Python package from a
# clean directory, with nothing of the source or build tree on sys.path.
# Usage: scripts/check_python_install.sh BUILD_DIR PYTHON SITE_DIR
#   SITE_DIR: where the package goes, relative to the prefix (IFEM_PYTHON_INSTALL_DIR)
set -euo pipefail
build=$(cd "$1" && pwd)
python=$2
site=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
mkdir "$tmp/clean"
cd "$tmp/clean"
PYTHONPATH="$tmp/prefix/$site" PYTHONNOUSERSITE=1 "$python" - "$tmp/prefix" <<'PY'
import sys
import numpy as np
import ifem
prefix = sys.argv[1]
assert ifem.__file__.startswith(prefix), f"imported {ifem.__file__}, not the installed copy"
V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.2]], float)
L, M = ifem.laplacian(V, [[0, 1, 2], [1, 3, 2]])
assert abs(L @ np.ones(4)).max() < 1e-12 and L.shape == (4, 4)
print(f"installed ifem {ifem.__version__} imports from {ifem.__file__}")
PY
