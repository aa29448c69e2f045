"""One self-contained HTML page of a mesh or point cloud and its data (the Python side of
``ifem view``): open it in any browser with WebGL, offline."""

import os

import numpy as np

from . import _ifem
from ._inputs import surface as _input


def view(V, F=None, path="ifem_view.html", *, title="", units="", vectors=None, symmetry=1,
         singularity=None, curves=None, triangulation=None, three_dir=None, **fields):
    """Writes a page showing the surface and everything given with it; same page as
    ``ifem view MESH --field ... --curves ... --triangulation ... -o PATH``.

    The page orbits (left drag), zooms (wheel) and pans (right drag); it colours the surface
    by any of ``fields`` with a perceptual colour map and a legend of the field's min / max
    (and ``units``), toggles isolines (10 bands), the input's wireframe, each curve group, the
    field glyphs, the singularities and the intrinsic edges, and saves the view as PNG. It
    embeds three.js (npm package ``three``, installed by ``scripts/setup.sh``) and the data, so
    it loads nothing from the network.

    Args:
        V: #V×3 positions, or a file's path (read as the CLI reads it).
        F: #F×3 vertex ids; ``None`` (or empty) for a point cloud, drawn as points.
        path: the page to write (str or os.PathLike), atomically.
        title: the page's title.
        units: units of the fields' values, shown in the legend.
        vectors: #V×3 tangent vectors (e.g. :func:`field`'s result): drawn as ``symmetry``
            short segments per vertex (the vector turned by 2πk/symmetry about the normal).
        symmetry: 1 vectors, 2 lines, 4 crosses (in [1, 6]).
        singularity: #V values, nonzero at singular vertices (marked: red +, blue −).
        curves: polylines on the surface: a list of k×3 arrays (one group named "curves"), a
            dict name -> list of k×3 arrays, or an OBJ file's path (as ``ifem geodesic -o``
            and ``--curves-out`` write).
        triangulation: a :class:`RefinedTriangulation` made on this mesh (:func:`refine`,
            :func:`load_refined`): its intrinsic edges traced over the input, one polyline each.
        three_dir: the three.js package directory (default: ``$IFEM_THREE_DIR``, then where
            ``scripts/setup.sh`` installs it).
        **fields: name=#V array of per-vertex values (non-finite values drawn grey).

    Returns:
        dict: ``path`` and the counts of ``fields``, ``curves``, ``glyphs``, ``singularities``,
        ``intrinsic_edges`` on the page.

    Raises:
        InvalidInput: an array of the wrong shape; a triangulation made on another mesh.
        IoError: three.js not found (the message says how to install it); the page cannot be
            written.
    """
    V, F, _ = _input(V, F)
    groups = []
    if curves is not None:
        if isinstance(curves, (str, bytes, os.PathLike)):
            name = os.path.splitext(os.path.basename(os.fsdecode(curves)))[0]
            groups = [(name, list(_ifem.read_polylines(os.fsdecode(curves))))]
        elif isinstance(curves, dict):
            groups = [(str(k), list(v)) for k, v in curves.items()]
        else:
            groups = [("curves", list(curves))]
    refined = None if triangulation is None else triangulation._h
    named = [(str(k), np.asarray(v, dtype=np.float64)) for k, v in fields.items()]
    info = _ifem.view(V, F, os.fspath(path), named, units, vectors, int(symmetry), singularity,
                      groups, refined, title, "" if three_dir is None else os.fspath(three_dir))
    return dict(info, path=os.fspath(path))


__all__ = ["view"]
