"""Geodesic curves on triangle meshes by FlipOut: paths, loops, networks, Bézier curves, and
single-source geodesics (what ``ifem geodesic`` computes).

FlipOut (Sharp & Crane 2020, "You Can Find Geodesic Paths in Triangle Meshes by Just Flipping
Edges") starts from a shortest path along mesh edges and flips the intrinsic edges inside every
bend of less than π until the curve runs straight across: the result is a geodesic (locally
shortest; not always the globally shortest curve). The surface never changes: curves are traced
over the input and returned as polylines of points on its faces.

Points are given as

- a **vertex id** (an integer, 0-based, a row of ``V``), or
- a **face point** ``(face, b0, b1, b2)``: a point inside row ``face`` of ``F`` with barycentric
  coordinates ``b0, b1, b2`` (≥ 0, summing to 1) for that row's corners ``F[face, 0]``,
  ``F[face, 1]``, ``F[face, 2]``. The CLI's ``face:F:u:v`` is ``(F, 1 - u - v, u, v)``.

FlipOut needs an edge-manifold, orientable triangle mesh (with or without boundary). On a
nonmanifold or non-orientable mesh, :func:`geodesic_path` with two points and
:func:`single_source_geodesics` still run: exact shortest paths on the mesh's tufted cover (every
face doubled, the copies glued around each edge; the surface :func:`ifem.exact_distance`
measures there; a path on it is a path on the mesh, of the same length; around an edge of 4+
faces it crosses only between faces next to each other about the edge). Loops, networks, paths
through more than two points, Bézier curves and ``single_source_flipout`` raise
:class:`ifem.NonManifoldInput` there (they need FlipOut's signposts), saying what does run.
"""

import os
from dataclasses import dataclass
from typing import List, Optional

import numpy as np

from . import _ifem
from ._errors import InvalidInput
from ._inputs import surface as _input


@dataclass(frozen=True)
class FlipOutReport:
    """What FlipOut did while shortening one or more curves together.

    Attributes:
        converged: every bend at a free joint is straight (wedge angles ≥ π − 1e-6).
        stopped_by: ``'converged'``, ``'iteration cap'``, ``'no progress'`` or ``'blocked'``
            (the remaining bends hold edges of other curves, which are never crossed).
        iterations: reroutes (FlipOut steps) performed.
        flips: intrinsic edge flips performed.
        blocked_joints: bent joints left when ``stopped_by == 'blocked'``.
        initial_length: total length of the curves before (as edge paths).
        final_length: total length after.
    """
    converged: bool
    stopped_by: str
    iterations: int
    flips: int
    blocked_joints: int
    initial_length: float
    final_length: float


@dataclass(frozen=True)
class GeodesicCurve:
    """One geodesic curve, traced over the input surface.

    Attributes:
        polyline: (#points, 3) float64 positions on the input surface, in order along the
            curve: where the curve crosses the input's edges, plus its vertices. A loop repeats
            its first point at the end. This is what ``ifem geodesic -o OUT.txt`` writes.
        length: the curve's length after FlipOut (intrinsic: exact on the surface; the 3D length
            of ``polyline`` agrees up to rounding and mollification).
        initial_length: the length of the shortest edge path FlipOut started from.
        closed: a loop.
        collapsed: a loop that shrank to a point (or around one vertex): a contractible loop;
            its ``polyline`` is then empty or tiny.
        points: (#given, 3) positions of the points the curve was given (vertices or face
            points), in the order given.
        report: FlipOut's report (shared by all curves of a network).
        start_won: the start path the geodesic came from, for a path between two points with
            ``start='best'`` or ``'guided'``: ``'shortest edge path'``, ``'G to b, S side'``
            or ``'G to a, reversed, S side'`` (G: ``exact geodesic`` or ``descent``; S:
            ``shorter``, ``left``, ``right``); as the CLI's ``start won:`` line. ``'exact
            path (...)'`` when the path is the exact distance's shortest path: FlipOut's
            geodesic was longer than the exact distance by more than 1e-9 (relative; the
            parenthesis names its start and the excess), or the mesh is nonmanifold (``'exact
            path (tufted cover)'``; ``report`` then counts no flips). ``''`` for other curves.
    """
    polyline: np.ndarray
    length: float
    initial_length: float
    closed: bool
    collapsed: bool
    points: np.ndarray
    report: FlipOutReport
    start_won: str


@dataclass(frozen=True)
class BezierCurve(GeodesicCurve):
    """A geodesic Bézier curve (a :class:`GeodesicCurve` with how it was made).

    Attributes:
        rounds: rounds of de Casteljau subdivision.
        control_points: control points after subdivision (degree · 2^rounds + 1).
        midpoints: vertices inserted as midpoints (the rest were existing vertices).
    """
    rounds: int
    control_points: int
    midpoints: int


@dataclass(frozen=True)
class GeodesicNetwork:
    """Curves shortened together (they never cross; they may share points).

    Attributes:
        curves: one :class:`GeodesicCurve` per curve, in the order given.
        report: FlipOut's report for all of them.
    """
    curves: List[GeodesicCurve]
    report: FlipOutReport

    @property
    def polylines(self):
        """The curves' polylines, a list of (#points, 3) arrays."""
        return [c.polyline for c in self.curves]

    @property
    def lengths(self):
        """The curves' lengths after FlipOut, a float64 array."""
        return np.array([c.length for c in self.curves])


@dataclass(frozen=True)
class SingleSourceGeodesics:
    """Geodesics from one source vertex to every vertex.

    Attributes:
        length: (#V,) float64: the length of the geodesic found to each vertex (0 at the
            source, ``inf`` where unreachable: another component, unreferenced vertices).
        paths: with ``return_paths=True``, one (#points, 3) polyline per vertex from the source
            to it (the source's: its own position; unreachable: an empty (0, 3) array); else None.
        flips: intrinsic edge flips performed (FlipOut; 0 with the exact distance).
        iterations: FlipOut reroutes performed.
        blocked: vertices whose geodesic was left bent (a wedge held an earlier path).
        exact: True when the geodesics are the exact distance's (the shortest ones).
        windows: the exact distance's windows (its work; 0 with FlipOut).
        tufted_cover: True when the mesh is not edge-manifold and orientable and the exact
            distance ran on its tufted cover (paths on the cover are paths on the mesh).
    """
    length: np.ndarray
    paths: Optional[List[np.ndarray]]
    flips: int
    iterations: int
    blocked: int
    exact: bool = False
    windows: int = 0
    tufted_cover: bool = False


def _report(d):
    return FlipOutReport(**{k: d[k] for k in FlipOutReport.__dataclass_fields__})


def _curves(curves, report):
    r = _report(report)
    return [GeodesicCurve(report=r, **c) for c in curves], r


def geodesic_path(V, F, points, loop=False, pin=False, mollify=1e-12, start="best"):
    """A geodesic through points of a mesh, in order (FlipOut).

    The curve starts as a shortest path along mesh edges through the points and is shortened by
    edge flips until it is straight everywhere except where it must bend: an open path keeps
    passing through every given point (it may bend there, like a string through rings); a loop
    (``loop=True``) is free to slide off its points (they only shape its start) unless
    ``pin=True``. A loop that can shrink to a point does (``collapsed``).

    FlipOut keeps the class of its start path around the vertices (which side of each it
    passes), so a path between two points starts from several paths (``start``) and the
    shortest geodesic is kept; a path between two points is never longer than the exact
    distance between them (where FlipOut's geodesic is, the exact shortest path is returned:
    ``start_won`` says so) while that distance fits the memory budget. On a nonmanifold or
    non-orientable mesh, two points only: the exact shortest path on its tufted cover (see the
    module's docstring).

    Same as ``ifem geodesic MESH --path P0,P1,... [--loop] [--pin] [--start S] -o OUT.txt``.

    Args:
        V: #V×3 positions.
        F: #F×3 vertex ids (an edge-manifold, orientable mesh; or any mesh for two points).
        points: ≥ 2 points, each a vertex id or a face point ``(face, b0, b1, b2)`` (see the
            module's docstring); consecutive points must differ (for a loop, the last and the
            first too: do not repeat the first point).
        loop: a closed curve through the points, back to the first.
        pin: keep the loop passing through its points (paths always are).
        mollify: relative mollification margin of the intrinsic triangulation (in [0, 1]);
            default 1e-12: the input's own lengths (only zero-area faces are lifted), as the
            CLI's ``geodesic`` and ``exact_distance``.
        start: FlipOut's start paths for a path between two points: ``"best"`` (edge paths
            along the faces the exact geodesic to each end crosses, then if none reaches the
            exact length the shortest edge path and paths down the exact distance, each
            shortened and moved over the vertices beside it while that shortens it; the
            shortest geodesic wins; a heat distance's descent when the exact distance exceeds
            the memory budget), ``"guided"`` (the same without the edge path) or
            ``"dijkstra"`` (the shortest edge path, one FlipOut: fastest, not always the
            shortest geodesic). Other curves always start from shortest edge paths.

    Returns:
        GeodesicCurve: ``polyline`` (#points×3), ``length``, ``initial_length``, ``report``
        (``converged``, ``iterations``, ...).

    Raises:
        InvalidInput: a vertex or face out of range, fewer than 2 points, a repeated point, bad
            barycentric coordinates, points on different connected components.
        NonManifoldInput: a mesh that is not edge-manifold and orientable, with a loop or
            more than two points.

    Example:
        >>> c = ifem.geodesic_path(V, F, [0, 500, (12, 0.2, 0.3, 0.5)])
        >>> c.length, c.report.converged, c.polyline.shape
    """
    if pin and not loop:
        raise InvalidInput("pin=True applies to loops (an open path always passes through its "
                           "points): set loop=True or drop pin")
    V, F, _ = _input(V, F)
    curves, report = _ifem.geodesic_curves(V, F, [(points, bool(loop), bool(pin))], ["points"],
                                           float(mollify), -1, False, str(start))
    return _curves(curves, report)[0][0]


def _network_item(item, i, pin):
    """(points, closed, pin) of one curve of geodesic_network's `curves`."""
    if isinstance(item, dict):
        unknown = set(item) - {"points", "loop", "pin"}
        if unknown or "points" not in item:
            raise InvalidInput(f"curves[{i}] must be a point list or a dict with keys 'points', "
                               f"'loop', 'pin'; got keys {sorted(item)}")
        return (item["points"], bool(item.get("loop", False)), bool(item.get("pin", pin)))
    return (item, False, bool(pin))


def read_network(path):
    """Reads the CLI's ``--network`` file into a list for :func:`geodesic_network` (the
    library's reader, the one ``ifem geodesic --network`` uses: same rules, same messages).

    One curve per line: ``path P0 P1 ...`` (an open geodesic through the points) or ``loop P0
    P1 ...`` (a closed one); each point a vertex id or ``face:F:u:v`` (the point with
    barycentric coordinates (1 − u − v, u, v) in face F; u, v ≥ 0 and u + v ≤ 1, else the line
    is refused); ``#`` starts a comment, blank lines are skipped.

    Returns:
        A list of dicts ``{'points': [...], 'loop': bool}``, face points as
        ``(F, 1 - u - v, u, v)``.

    Raises:
        IoError: an unreadable file or a malformed line (naming ``path:line``).
    """
    return _ifem.read_network(os.fspath(path))


def geodesic_network(V, F, curves, pin=False, mollify=1e-12, max_iterations=None,
                     accept_partial=False):
    """Several geodesic paths and loops, shortened together (FlipOut on a curve network).

    The curves never cross each other (a bend that would need to flip an edge of another curve
    stays: ``report.stopped_by == 'blocked'``); they may share points. Same as ``ifem geodesic
    MESH --network FILE -o OUT.txt``.

    Args:
        V: #V×3 positions.
        F: #F×3 vertex ids (an edge-manifold, orientable mesh).
        curves: a list with one entry per curve, each either a list of points (an open path
            through them, see :func:`geodesic_path`) or a dict ``{'points': [...], 'loop':
            True, 'pin': False}`` (``loop``, ``pin`` optional); or the path of a CLI network file
            (see :func:`read_network`).
        pin: the default ``pin`` of loops (keep passing through their points).
        mollify: relative mollification margin.
        max_iterations: FlipOut's cap on reroutes, all curves together (None: 10 × #E + 1000;
            ``--max-iterations``).
        accept_partial: return curves that stopped at the cap as they are (not geodesic;
            ``report.stopped_by == 'iteration cap'``); False raises (``--accept-partial``).

    Returns:
        GeodesicNetwork: ``curves`` (a :class:`GeodesicCurve` each), ``report``, and the
        conveniences ``polylines`` and ``lengths``.

    Raises:
        InvalidInput: as :func:`geodesic_path`, naming the curve (``curves[2][1]``); curves
            that stopped at the iteration cap without ``accept_partial`` (stating what was
            reached).
        IoError: a network file that cannot be read.

    Example:
        >>> net = ifem.geodesic_network(V, F, [[0, 100], {'points': [5, 60, 300], 'loop': True}])
        >>> net.lengths, net.report.converged
    """
    if isinstance(curves, (str, os.PathLike)):
        curves = read_network(curves)
    if isinstance(curves, np.ndarray) or not isinstance(curves, (list, tuple)):
        raise InvalidInput("curves must be a list of curves (point lists or dicts) or a network "
                           f"file's path, got {type(curves).__name__}")
    V, F, _ = _input(V, F)
    items = [_network_item(c, i, pin) for i, c in enumerate(curves)]
    names = [f"curves[{i}]" for i in range(len(items))]
    cap = -1 if max_iterations is None else max_iterations
    if isinstance(cap, (bool, np.bool_)) or not isinstance(cap, (int, np.integer)) or cap < -1:
        raise InvalidInput(f"max_iterations must be an integer ≥ 0 (or None), got {cap!r}")
    out, report = _ifem.geodesic_curves(V, F, items, names, float(mollify), int(cap),
                                        bool(accept_partial))
    cs, r = _curves(out, report)
    return GeodesicNetwork(curves=cs, report=r)


def bezier_curve(V, F, control_points, rounds=4, mollify=1e-12, memory_budget=None):
    """A geodesic Bézier curve with the given control points (de Casteljau with geodesics).

    Each round splits every Bézier piece at t = 1/2, taking midpoints halfway along FlipOut
    geodesics between the current control points (inserted as vertices); after ``rounds``
    rounds the control polygon, joined by geodesics, is the curve: smooth-looking, through the
    first and last control points only. Same as ``ifem geodesic MESH --path P0,P1,...
    --bezier ROUNDS -o OUT.txt``.

    Args:
        V: #V×3 positions.
        F: #F×3 vertex ids (an edge-manifold, orientable mesh).
        control_points: ≥ 2 points (vertex ids or face points), consecutive ones distinct; the
            curve's degree is their count − 1.
        rounds: subdivision rounds in [0, 16] (0: the geodesic control polygon itself); the
            control polygon grows to degree · 2^rounds + 1 points.
        mollify: relative mollification margin.
        memory_budget: GB for the vertices the curve adds, estimated up front (d(d+1)/2 ·
            (2^rounds − 1) for degree d, 4 KiB each; None: half the physical memory;
            ``--memory-budget``).

    Returns:
        BezierCurve: a :class:`GeodesicCurve` (``polyline``, ``length``, ``report``) with
        ``rounds``, ``control_points`` and ``midpoints``.

    Raises:
        InvalidInput: bad control points (as :func:`geodesic_path`, named
            ``control_points[i]``) or ``rounds`` out of range; before any work, rounds whose
            estimate exceeds ``memory_budget`` or whose segments fall below 1/16 of the mesh's
            mean edge length (the message gives the figures and the most rounds that fit).
    """
    if isinstance(rounds, (bool, np.bool_)) or not isinstance(rounds, (int, np.integer)):
        raise InvalidInput(f"rounds must be an integer in [0, 16], got {rounds!r}")
    V, F, _ = _input(V, F)
    budget = 0.0 if memory_budget is None else float(memory_budget) * 1e9
    if not budget >= 0.0:
        raise InvalidInput(f"memory_budget must be a number of GB > 0 (or None), got "
                           f"{memory_budget!r}")
    curves, report = _ifem.bezier_curve(V, F, control_points, int(rounds), float(mollify),
                                        budget)
    c = curves[0]
    return BezierCurve(report=_report(report), rounds=int(rounds),
                       control_points=report["bezier_control_points"],
                       midpoints=report["bezier_midpoints"], **c)


def single_source_geodesics(V, F, source, return_paths=False, mollify=1e-12, progress=None,
                            single_source_flipout=False):
    """Geodesics from one vertex to every vertex, and their lengths.

    By default the shortest geodesics, from the exact polyhedral distance (window propagation
    on the mesh's own faces, as ``ifem distance --exact``; each path is traced back through its
    windows). With ``single_source_flipout=True`` (and when the exact distance's windows exceed
    the memory budget) a Dijkstra search from ``source`` that straightens every path by FlipOut
    before accepting it, holding the paths accepted earlier fixed; each length is then that
    geodesic's: ≥ the exact distance, equal to it wherever the geodesic found is the shortest
    one (94–100% of the vertices on the reference meshes; fewer on meshes of slivers). On a
    nonmanifold or non-orientable mesh: the exact distance on its tufted cover (``tufted_cover``
    True), as :func:`ifem.exact_distance` there. Same as
    ``ifem geodesic MESH --all-from S -o OUT.txt [--single-source-flipout]``.

    Args:
        V: #V×3 positions.
        F: #F×3 vertex ids (any triangle mesh; nonmanifold: through the tufted cover).
        source: the source vertex id.
        return_paths: also trace every geodesic over the input (one polyline per vertex; with
            FlipOut it costs about as much as the search again).
        mollify: relative mollification margin.
        progress: None (default: nothing is reported, nothing printed) or a callable
            ``progress(fraction, stage)``, stage ``"single-source geodesics"``: the vertices
            accepted over #V (0 first, non-decreasing, exactly 1 last).
        single_source_flipout: build the geodesics by FlipOut instead of the exact distance.

    Returns:
        SingleSourceGeodesics: ``length`` (#V, ``inf`` where unreachable), ``paths`` (when
        asked), ``flips``, ``iterations``, ``blocked``, ``exact``, ``windows``,
        ``tufted_cover``.

    Raises:
        InvalidInput: ``source`` out of range or not an integer; on a nonmanifold mesh the
            exact distance over the memory budget.
        NonManifoldInput: ``single_source_flipout`` on a mesh that is not edge-manifold and
            orientable (FlipOut needs signposts).
    """
    V, F, _ = _input(V, F)
    length, paths, info = _ifem.single_source_geodesics(V, F, source, bool(return_paths),
                                                        float(mollify), progress,
                                                        bool(single_source_flipout))
    return SingleSourceGeodesics(length=length, paths=paths, **info)


def geodesic(V, F=None, points=None, *, loop=False, pin=False, bezier=None, network=None,
             all_from=None, return_paths=False, mollify=1e-12, max_iterations=None,
             accept_partial=False, memory_budget=None, start="best", progress=None,
             single_source_flipout=False):
    """Geodesic curves by FlipOut, as ``ifem geodesic``: one function, the CLI's modes as
    keywords. Give exactly one of

    - ``points``: a path through them (``--path``), closed with ``loop=True`` (``--loop``,
      ``pin`` as ``--pin``), or the control points of a Bézier curve with ``bezier=ROUNDS``
      (``--bezier``): :func:`geodesic_path` / :func:`bezier_curve`;
    - ``network``: a network file's path or a list of curves (``--network``):
      :func:`geodesic_network`;
    - ``all_from``: a source vertex (``--all-from``): :func:`single_source_geodesics`.

    ``V`` may be a mesh file's path (F then None), as the CLI's MESH. ``max_iterations`` and
    ``accept_partial`` (``--max-iterations``, ``--accept-partial``) go to networks,
    ``memory_budget`` (``--memory-budget``) to Bézier curves, ``start`` (``--start``) to
    :func:`geodesic_path`, ``progress`` (a callable ``progress(fraction, stage)``; None: none)
    and ``single_source_flipout`` (``--single-source-flipout``) to
    :func:`single_source_geodesics`.

    Returns:
        GeodesicCurve, BezierCurve, GeodesicNetwork or SingleSourceGeodesics, as the mode's
        function.

    Raises:
        InvalidInput: not exactly one mode, a keyword of another mode, and as the mode's
            function.
    """
    modes = [name for name, x in (("points", points), ("network", network),
                                  ("all_from", all_from)) if x is not None]
    if len(modes) != 1:
        raise InvalidInput("give exactly one of points, network, all_from (the CLI's --path, "
                           f"--network, --all-from), got {modes or 'none'}")
    if bezier is not None and (points is None or loop):
        raise InvalidInput("bezier takes points as the control points of an open curve")
    if loop and points is None:
        raise InvalidInput("loop closes the points' curve (in a network, write loops as dicts "
                           "{'points': [...], 'loop': True} or 'loop' lines)")
    if return_paths and all_from is None:
        raise InvalidInput("return_paths applies to all_from (single-source geodesics)")
    if progress is not None and all_from is None:
        raise InvalidInput("progress applies to all_from (single-source geodesics)")
    if single_source_flipout and all_from is None:
        raise InvalidInput("single_source_flipout applies to all_from (single-source geodesics)")
    if (max_iterations is not None or accept_partial) and network is None:
        raise InvalidInput("max_iterations and accept_partial apply to network (FlipOut on "
                           "a curve network)")
    if memory_budget is not None and bezier is None:
        raise InvalidInput("memory_budget applies to bezier (the vertices a Bézier curve adds)")
    V, F, _ = _input(V, F)
    if all_from is not None:
        return single_source_geodesics(V, F, all_from, return_paths, mollify, progress,
                                       single_source_flipout)
    if network is not None:
        return geodesic_network(V, F, network, pin, mollify, max_iterations, accept_partial)
    if bezier is not None:
        if pin:
            raise InvalidInput("pin applies to loops, not to a Bézier curve")
        return bezier_curve(V, F, points, bezier, mollify, memory_budget)
    return geodesic_path(V, F, points, loop, pin, mollify, start)


__all__ = ["geodesic", "geodesic_path", "geodesic_network", "bezier_curve", "single_source_geodesics",
           "read_network", "GeodesicCurve", "BezierCurve", "GeodesicNetwork",
           "SingleSourceGeodesics", "FlipOutReport"]
