"""Isolines: the level sets ``{f = c}`` of a per-vertex field as polylines on the surface (what
``ifem isolines`` computes, marching triangles on the input mesh).

f is linear on each triangle; every isoline point lies on an input edge where f crosses c, with f
interpolated there equal to c. A vertex exactly at c counts as above c, so a curve through a
vertex passes through it once (no duplicate point, no gap). Vertices whose value is not finite
(the ``inf`` of unreachable vertices in a distance) cut no curve.
"""

import os
from dataclasses import dataclass
from typing import List

import numpy as np

from . import _ifem
from ._errors import InvalidInput
from ._inputs import is_path


@dataclass(frozen=True)
class Isolines:
    """The isolines of one field at one or more levels, as flat arrays (k pieces, n points).

    Piece ``i`` is ``points[offsets[i]:offsets[i + 1]]``, in order along the curve (direction
    unspecified); ``closed[i]``: the curve comes back to its first point (not repeated).

    Attributes:
        points: (n, 3) float64 positions on the input surface.
        faces: (n,) int32: a triangle (row of F) holding each point; with ``bary`` (n, 3), the
            barycentric coordinates for that row's corners: the point as a surface point.
        below, above: (n,) int32: the crossed edge's ends, f[below] < c ≤ f[above]; both the
            same vertex where it is exactly at c.
        t: (n,) float64: the point is ``(1 - t) * V[below] + t * V[above]``.
        offsets: (k + 1,) int32: where each piece starts in the point arrays.
        level: (k,) int32: index of each piece's level in ``levels``.
        value: (k,) float64: each piece's level c.
        closed: (k,) bool.
        levels: the levels asked for (``values``, or the ``count`` evenly spaced ones).
    """
    points: np.ndarray
    faces: np.ndarray
    bary: np.ndarray
    below: np.ndarray
    above: np.ndarray
    t: np.ndarray
    offsets: np.ndarray
    level: np.ndarray
    value: np.ndarray
    closed: np.ndarray
    levels: List[float]

    def __len__(self):
        return len(self.closed)

    def polylines(self):
        """Each piece's (n_i, 3) points, a closed one with its first point repeated at the end
        (ready to draw)."""
        out = []
        for i in range(len(self)):
            p = self.points[self.offsets[i]:self.offsets[i + 1]]
            out.append(np.vstack([p, p[:1]]) if self.closed[i] else p.copy())
        return out


def isolines(V, F=None, f=None, *, values=None, count=None):
    """The isolines of a per-vertex field ``f`` at the given levels, as ``ifem isolines``.

    Args:
        V: #V×3 positions, or a mesh file's path (with ``F`` None); a PLY output of another
            command (``ifem distance -o d.ply``) holds both the mesh and its fields.
        F: #F×3 vertex ids (a mesh with faces: point clouds have no isolines).
        f: #V values (non-finite ones cut no curve), or with a path: the name of one of the
            file's per-vertex properties (``"distance"``).
        values: the levels, each within f's range over its finite values.
        count: instead of ``values``: ``count`` levels evenly spaced strictly inside that
            range, ``min + i (max - min) / (count + 1)``, i = 1 .. count.

    Returns:
        :class:`Isolines` (flat arrays; ``.polylines()`` for a list of point arrays).

    Raises:
        InvalidInput: sizes, ids, both or neither of ``values`` and ``count``, a level outside
            f's range (the message gives the range), a property the file does not have.

    Example:
        >>> d = ifem.distance(V, F, 0)
        >>> iso = ifem.isolines(V, F, d, count=10)
        >>> for p in iso.polylines(): ...
    """
    if is_path(V) and F is None:
        V, F, info = _ifem.read_mesh(os.fsdecode(V))
        if isinstance(f, str):
            props = info.get("vertex_properties", {})
            if f not in props:
                raise InvalidInput(f"f: the file has no per-vertex property {f!r} (it has: "
                                   f"{', '.join(props) or 'none'})")
            f = props[f]
    elif isinstance(f, str):
        raise InvalidInput("f: a property name needs V to be a file's path")
    if F is None:
        raise InvalidInput("F: isolines need a mesh with faces")
    if count is not None and (isinstance(count, bool) or not isinstance(count, (int, np.integer))):
        raise InvalidInput(f"count must be an integer, got {count!r}")
    if values is not None and np.ndim(values) == 0:
        values = [values]
    d = _ifem.isolines(V, F, f, values, None if count is None else int(count))
    return Isolines(**d)


__all__ = ["Isolines", "isolines"]
