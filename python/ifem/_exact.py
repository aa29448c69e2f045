"""Exact polyhedral geodesic distance (window propagation), as ``ifem distance --exact``."""

from . import _ifem
from ._errors import InvalidInput
from ._inputs import surface as _input
from ._solvers import _faces, _real

__all__ = ["exact_distance"]


def exact_distance(V, F=None, sources=None, *, refine=False, min_angle=25.0, resolution=0.0,
                   mollify=1e-12, path="auto", memory_budget=None, paths_from=None,
                   return_info=False):
    """Exact geodesic distance from source vertices, as ``ifem distance --exact``.

    Window propagation over the faces of the intrinsic triangulation (Chen–Han / Xin–Wang with
    pruning), from edge lengths alone: it runs on the input's own faces (not flipped: on scans
    the intrinsic Delaunay faces need several times the windows), on the tufted cover of a
    nonmanifold mesh (``path="tufted"`` or automatically) and after refinement
    (``refine=True``: the same surface, the same distances). No approximation: a reference to
    measure approximate distances against. Time grows about as #F^1.5 (the windows); memory is
    that of the windows waiting at once (64 bytes each), of all of them with ``paths_from``.

    Args:
        V: #V×3 vertex positions, or a mesh file's path (F then None).
        F: #F×3 vertex ids.
        sources: vertex ids (the distance is to the nearest).
        refine, min_angle, resolution: intrinsic Delaunay refinement first (angles only by
            default); results on the input's vertices either way.
        mollify, path: as in :class:`HeatDistanceSolver`; mollify defaults to 1e-12 here (the
            distances of the input's own lengths: only a face of zero area, which windows
            would not cross, is lifted, every edge by about 1e-12 of the mean; a larger margin
            lengthens every edge of a mesh with a face below it).
        memory_budget: None (half the physical memory) or gigabytes the windows may take; over
            it, :class:`InvalidInput` states the figures.
        paths_from: None or vertex ids: also return, for each, the shortest path back to its
            nearest source as a (k, 3) array of points on the surface (vertex first, source
            last; edge crossings between). Needs ``refine=False``; the distances are the
            same.
        return_info: also return a dict (windows, and the preparation as in ``eigen``).

    Returns:
        #V float64 distances (``inf`` where no source reaches); with ``paths_from``, the tuple
        (distances, list of paths); with ``return_info``, the info dict last.
    """
    V, F, _ = _input(V, F, None)
    if sources is None:
        raise InvalidInput("exact_distance needs sources (vertex ids)")
    if not refine and (min_angle != 25.0 or resolution != 0.0):
        raise InvalidInput("min_angle, resolution only apply with refine=True")
    r = (_real(min_angle, "min_angle"), _real(resolution, "resolution")) if refine else None
    budget = 0.0 if memory_budget is None else _real(memory_budget, "memory_budget")
    if memory_budget is not None and not budget > 0:
        raise InvalidInput(f"memory_budget must be None or > 0 gigabytes, got {memory_budget!r}")
    if not isinstance(path, str):
        raise InvalidInput(f"path must be a string, got {path!r}")
    d, windows, paths, info = _ifem.exact_distance(V, _faces(F), sources, _real(mollify, "mollify"),
                                                   path, r, budget, paths_from)
    info["windows"] = windows
    out = (d,) if paths_from is None else (d, list(paths))
    if return_info:
        out = out + (info,)
    return out[0] if len(out) == 1 else out
