"""Tangent fields: the smoothest n-direction field (vectors, lines, crosses), free or aligned."""

import numpy as np

from . import _ifem
from ._curves import _specs


def direction_field(V, F, symmetry=1, align_boundary=False, constraint_vertices=None,
                    directions=None, mollify=1e-5, return_info=False, *, curves=None):
    """The smoothest n-direction field on a mesh, as unit 3D tangent vectors per vertex.

    The field is the smallest eigenvector of the connection Laplacian of the intrinsic
    Delaunay triangulation (Knöppel, Crane, Pinkall, Schröder 2013), or, with constraints, the
    smoothest field through them (harmonic in the power representation). Same as
    ``ifem field MESH --symmetry N [--align-boundary] [--constraints FILE] [--curves FILE]``.

    With ``curves``, the field conforms to curves drawn through the mesh's vertices (the
    thesis' Figure 10 left): they are inserted as edges of a constrained intrinsic Delaunay
    triangulation exactly as for :func:`curve_poisson` (FlipOut geodesics, Bézier curves), and
    the field is held along them at every vertex on them (inside a curve, the mean of the edge
    leaving and the continuation of the edge arriving, in the n-th power; for n = 1 the vectors
    point the way the curve runs). On a flat mesh, a loop through equally spaced vertices of a
    circle gives a field exactly tangent to the circle there.

    Args:
        V: #V×3 positions.
        F: #F×3 vertex ids.
        symmetry: n ≥ 1 — 1 vectors, 2 lines, 4 crosses.
        align_boundary: hold the field along the boundary (meshes that take the manifold path).
        constraint_vertices: vertex ids where a direction is held (with ``directions``).
        directions: #K×3 directions in space, projected to the tangent plane at each vertex.
        mollify: relative mollification margin.
        return_info: also return a dict (path, ``singular_faces``, ``total_index`` — n·χ on a
            closed surface —, ``face_singularity`` — #F int array: the index of each face of
            F, in units of 1/n, from the field at its corners and the transport along its
            edges; sums to n·χ on a closed mesh; what ``ifem field -o OUT.ply`` writes as the
            face property ``singularity``; empty if unknown —, ``constrained``, ``energy``,
            ...; with curves, ``curves``: what inserting them did, as :func:`curve_poisson`'s
            info).
        curves: None, or curves to align the field to: a list of :class:`Curve` (or dicts of
            its arguments), one Curve, or a curves file's path (as :func:`curve_poisson`; the
            curves' values are not used and may be omitted, e.g. ``ifem.Curve([3, 8, 20, 31],
            bezier=True)``). Needs an edge-manifold, orientable mesh.

    Returns:
        ``vectors`` (#V×3: a unit tangent vector per vertex, one of the n directions; 0 where
        the field has no direction), ``angle`` (#V: that direction's angle in the vertex's own
        coordinate, 0 along its first edge, counter-clockwise with the faces' orientation),
        ``singularity`` (#V: indices in units of 1/n of the singular faces, each counted on one
        of its corners), and ``info`` when asked.

    Raises:
        InvalidInput: bad arrays, symmetry < 1, a constraint vertex out of range or a direction
            normal to the surface, a mesh that is not edge-manifold and orientable (its tufted
            cover's vertices have several fans: directions there would not be the surface's),
            a bad curve (named ``curves[i]`` or ``file:line``), two curves sharing an edge.
        IoError: an unreadable curves file.

    Example:
        >>> vectors, angle, singularity = ifem.direction_field(
        ...     V, F, symmetry=4, curves=[ifem.Curve([0, 40, 77]), ifem.Curve([5, 9, 13],
        ...                                                            closed=True)])
    """
    specs = None if curves is None else _specs(curves)
    vectors, angle, singularity, info = _ifem.direction_field(
        V, F, int(symmetry), bool(align_boundary), constraint_vertices, directions,
        float(mollify), specs)
    out = (np.ascontiguousarray(vectors), angle, singularity)
    return out + (info,) if return_info else out


class VectorHeatSolver:
    """The Vector Heat Method (Sharp, Soliman, Crane 2019) on a mesh: factors once, then
    parallel transport and logarithmic maps cost a few back-substitutions each. Same as
    ``ifem transport`` / ``ifem logmap``; like potpourri3d's ``MeshVectorHeatSolver``, with 3D
    vectors in and out.

    Args:
        V: #V×3 positions.
        F: #F×3 vertex ids (a mesh; on the tufted path of a nonmanifold mesh the directions are
            not meaningful).
        mollify: relative mollification margin.
    """

    def __init__(self, V, F, mollify=1e-5):
        self._solver = _ifem.VectorHeat(V, F, float(mollify))

    def transport(self, source, vector):
        """Parallel transport of a 3D vector at vertex ``source`` (projected to its tangent
        plane, length kept) to every vertex along shortest geodesics: #V×3 tangent vectors (0
        where nothing arrives)."""
        return self._solver.transport(int(source), np.asarray(vector, float).reshape(1, 3))

    def log_map(self, source):
        """The logarithmic map about vertex ``source``: #V×2 Riemannian coordinates
        (u, v) = d·(cos θ, sin θ), d the geodesic distance, θ the direction at the source
        counter-clockwise from its first edge's direction."""
        return self._solver.log_map(int(source))

    @property
    def info(self):
        """What preparing the surface chose and did (path, flips, ...)."""
        return self._solver.info()


__all__ = ["direction_field", "VectorHeatSolver"]
