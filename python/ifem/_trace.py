"""Straight geodesics (the exponential map): from a point of a triangle mesh, the line that
never turns, leaving in a given direction, for a given length (what ``ifem trace`` computes).

The ray is traced face by face over the input's own triangles (each unfolded into the plane of
the last; no flips, no mollification), so its polyline lies on the input and its length is the
one asked, to rounding (unless it stops at the boundary).

The start is a vertex id (an integer) or a face point ``(face, b0, b1, b2)`` (row ``face`` of
``F``, barycentric coordinates for its corners, ≥ 0, summing to 1), as in :mod:`ifem.geodesic`;
the CLI's ``face:F:u:v`` is ``(F, 1 - u - v, u, v)``. A ray's end is given back in the same
form, so it can start the next ray.

The direction is 3D and need not be tangent: at a face point it is projected onto the face's
plane; at a vertex onto the plane normal to the angle-weighted vertex normal, where the projected
edges cut the plane into wedges, each mapped linearly onto the corner between the same two edges
(so a direction along an edge runs along it; at a flat vertex nothing changes). At a boundary
vertex a direction off the surface is refused, and a direction along the normal everywhere.

Needs an edge-manifold, orientable triangle mesh (:class:`ifem.NonManifoldInput` otherwise).
"""

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from . import _ifem
from ._errors import InvalidInput
from ._inputs import surface as _input


@dataclass(frozen=True)
class GeodesicRay:
    """One traced ray.

    Attributes:
        polyline: (#points, 3) float64: the start, every edge crossing, the end, on the input's
            faces (what ``ifem trace -o OUT.txt`` writes).
        end: the end as a face point ``(face, b0, b1, b2)`` (a valid ``start``).
        end_vertex: the input vertex the ray ends on (a weight within 1e-12 of 1), else None.
        end_position: the end's 3D position.
        length: the polyline's length: the length asked unless ``hit_boundary``.
        hit_boundary: stopped at a boundary side before the length asked.
        slides: boundary sides it slid along (``slide=True``).
        start_direction: the unit 3D tangent it left in (the direction made tangent).
        end_direction: the unit 3D tangent at the end.
    """
    polyline: np.ndarray
    end: Tuple[int, float, float, float]
    end_vertex: Optional[int]
    end_position: np.ndarray
    length: float
    hit_boundary: bool
    slides: int
    start_direction: np.ndarray
    end_direction: np.ndarray


def _start(start):
    """(vertex, face, b0, b1, b2) for the binding: vertex ≥ 0, or −1 and a face point."""
    if isinstance(start, (int, np.integer)) and not isinstance(start, bool):
        if start < 0:
            raise InvalidInput(f"start = {start}: a vertex id must be ≥ 0")
        return [float(start), 0.0, 0.0, 0.0, 0.0]
    try:
        face, b0, b1, b2 = start
        fface = float(face)
        values = [float(b0), float(b1), float(b2)]
    except (TypeError, ValueError):
        raise InvalidInput("start must be a vertex id (an integer) or a face point (face, b0, b1, "
                           f"b2), got {start!r}") from None
    if not (np.isfinite(fface) and fface == int(fface) and fface >= 0):
        raise InvalidInput(f"start = {start!r}: the face must be an integer ≥ 0")
    return [-1.0, fface] + values


def _ray(d):
    return GeodesicRay(polyline=d["polyline"], end=tuple(d["end"]), end_vertex=d["end_vertex"],
                       end_position=np.array(d["end_position"]), length=d["length"],
                       hit_boundary=d["hit_boundary"], slides=d["slides"],
                       start_direction=np.array(d["start_direction"]),
                       end_direction=np.array(d["end_direction"]))


def trace(V, F=None, start=None, direction=None, length=None, *, slide=False):
    """Straight geodesics from ``start`` in ``direction`` for ``length``, as ``ifem trace``.

    Args:
        V: (#V, 3) positions, or a mesh file's path (F then None), as the CLI's MESH.
        F: (#F, 3) vertex ids.
        start: a vertex id or a face point ``(face, b0, b1, b2)``.
        direction: (3,) one direction (``--direction``), or (k, 3) k rays from the same start
            (``--directions``); any length > 0, made tangent as the module says.
        length: how far to go (≥ 0, the mesh's length unit).
        slide: at the boundary go on along it (``--slide``); default: stop there.

    Returns:
        GeodesicRay for one direction, a list of them for a (k, 3) array.

    Raises:
        InvalidInput: a bad start (out of range, not a point), a zero, non-finite or normal
            direction, one off the surface at a boundary vertex, a negative length.
        NonManifoldInput: the mesh is not edge-manifold and orientable.
        TraceError: the ray crossed a face without area.
    """
    if start is None or direction is None or length is None:
        raise InvalidInput("trace needs start, direction and length")
    V, F, _ = _input(V, F)
    if F is None:
        raise InvalidInput("trace needs a triangle mesh (F is None: a point cloud)")
    d = np.asarray(direction, dtype=np.float64)
    single = d.ndim == 1
    if d.shape[-1:] != (3,) or d.ndim > 2 or d.size == 0:
        raise InvalidInput(f"direction must have shape (3,) or (k, 3), got {d.shape}")
    length = float(length)
    if not (np.isfinite(length) and length >= 0):
        raise InvalidInput(f"length = {length!r} must be finite and ≥ 0")
    rays = _ifem.trace_rays(V, F, _start(start), d.ravel().tolist(), length, bool(slide))
    out = [_ray(r) for r in rays]
    return out[0] if single else out


# potpourri3d's name (GeodesicTracer.trace_geodesic_from_vertex / _from_face): the same function
trace_geodesic = trace

__all__ = ["GeodesicRay", "trace", "trace_geodesic"]
