"""Signed distance by the signed heat method (Feng & Crane 2024, "A Heat Method for Generalized
Signed Distance"): what ``ifem distance --signed`` computes."""

import numpy as np

from . import _ifem
from ._curves import _flipout_cap, _refine, _specs
from ._errors import InvalidInput
from ._inputs import surface as _input


def signed_distance(V, F=None, curves=None, *, points=None, point_normals=None, normals=None,
                    time_factor=1.0, level_set="zero-set", refine=False, min_angle=25.0,
                    resolution=0.4, max_area=0.0, max_insertions=None, conform=True,
                    path="auto", knn=30, mollify=1e-5, max_iterations=None, accept_partial=False,
                    return_info=False, correspondence="integer"):
    """Signed distance to curves or to oriented points, on meshes and point clouds.

    The sources' normals are diffused by the vector heat method (one step (M + t·L∇) Y = Y₀,
    t = m·h²), normalized to X = Y/|Y|, then L φ = div X gives φ, and the level set fixes its
    constant. Curves may be open, broken, or have gaps: the diffused normals fill in, so the sign
    stays right around them. |φ| is the distance near the sources, a smooth generalization far
    off. Same as ``ifem distance MESH --signed --curves FILE`` / ``--points FILE``.

    Sign: for curves, seen from the side the faces' normals point to and walking along the curve
    (from its first vertex to its second), the right-hand side is positive and the left-hand
    side negative (a counter-clockwise loop is negative inside). For oriented points, the side
    their normals point to is positive.

    Args:
        V: #V×3 positions, or a mesh / point-cloud file (then F is None).
        F: #F×3 vertex ids; None or empty for a point cloud.
        curves: as :func:`curve_distance` (an edge-manifold, orientable mesh; values ignored).
        points: instead of curves, #K vertex ids of oriented points.
        point_normals: #K×3 normals of the points, along the surface (their projection to the
            tangent plane is used; a normal perpendicular to the surface is refused).
        normals: per-vertex normals of a point cloud (as elsewhere), optional.
        time_factor: m in t = m·h² (> 0); larger smooths over gaps and noise.
        level_set: 'zero-set' (φ = 0 on the curves' vertices or the points) or 'mean' (the mean
            of φ there is 0; the zero level may move off a broken or noisy curve).
        refine, min_angle, resolution, max_area, max_insertions, conform, correspondence: with
            curves, constrained refinement first (see :func:`curve_poisson`; correspondence
            ``"integer"`` by default or ``"signposts"``, the CLI's ``--correspondence``).
        path, knn: with points, the surface path ('auto', 'manifold', 'tufted', 'pointcloud') and
            neighbours on the point-cloud path. Points run on every path, never refined.
        mollify: relative mollification margin.
        max_iterations, accept_partial: FlipOut's cap on the curves (see :func:`curve_poisson`).
        return_info: also return a dict (the surface, ``time_step``, ``unreached_vertices``,
            ``unresolved_vertices``).

    Returns:
        ``d`` (#V float64; NaN on vertices of components without a source), and the info dict
        when asked.

    Raises:
        InvalidInput: neither or both of curves and points, bad points or normals, bad options,
            curves on a surface that is not edge-manifold and orientable.
        SolverError: if a factorization fails.
    """
    if (curves is None) == (points is None):
        raise InvalidInput("signed_distance needs curves or points (with point_normals), one of "
                           "them")
    V, F, normals = _input(V, F, normals)
    specs = None if curves is None else _specs(curves)
    if points is not None:
        points = np.asarray(points)
        point_normals = None if point_normals is None else np.asarray(point_normals, float)
    d, info = _ifem.signed_distance(
        V, F, normals, specs, points, point_normals,
        _refine(refine, min_angle, resolution, max_area, max_insertions, conform,
                correspondence),
        float(time_factor), str(level_set), float(mollify), str(path), int(knn),
        _flipout_cap(max_iterations), bool(accept_partial))
    return (d, info) if return_info else d


__all__ = ["signed_distance"]
