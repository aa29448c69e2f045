"""Boundary-value problems with data on curves (diffusion curves): what ``ifem poisson --curves``
and ``ifem distance --curves`` compute.

Curves are drawn through a mesh's vertices: geodesic paths and loops (FlipOut) or geodesic
Bézier curves. They become edges of a constrained intrinsic Delaunay triangulation (never
flipped; split but never crossed by refinement), so the data they carry is held *exactly along
the curves*, not on a staircase of mesh vertices near them:

- :func:`curve_poisson` solves (L + c·M) u = M f with u = the curves' values on them (values
  linear in arc length between the given ones); a *slit* cuts the surface open so u may jump
  across it, with its own values on each side.
- :func:`curve_distance` is the geodesic distance to the nearest curve (heat method; exactly 0 on
  the curves).

Results are on the input's vertices, in the input's order. Curves need an edge-manifold,
orientable triangle mesh (with or without boundary).
"""

import numbers
import os

import numpy as np

from . import _ifem
from ._errors import InvalidInput
from ._solvers import _path_bounds

_MAX_ROUNDS = 16


def _reals(x, what, origin):
    """None → empty; a number → [x]; a 1-D sequence → float64 array (finiteness is checked by
    the library, with the curve's name)."""
    if x is None:
        return np.zeros(0)
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInput(f"{origin}: {what} must be a number or a list of numbers, "
                           f"got {x!r}") from None
    if a.ndim > 1:
        raise InvalidInput(f"{origin}: {what} must be a number or a 1-D list, got shape "
                           f"{a.shape}")
    return np.atleast_1d(a).copy()


def _vertex_ids(vertices, origin):
    a = np.asarray(vertices)
    if a.size == 0:
        a = a.astype(np.int64)
    if a.ndim != 1 or a.dtype.kind not in "iu":
        raise InvalidInput(f"{origin}: vertices must be a 1-D list of vertex ids (integers), got "
                           f"dtype {a.dtype} and shape {a.shape}")
    if a.dtype.kind == "u" and a.size and a.max() > np.iinfo(np.int64).max:
        raise InvalidInput(f"{origin}: vertex id {a.max()} is too large")
    a = a.astype(np.int64)
    negative = np.flatnonzero(a < 0)
    if negative.size:
        i = int(negative[0])
        raise InvalidInput(f"{origin}: vertices[{i}] = {a[i]} is negative (vertex ids are "
                           "0-based rows of V)")
    return a


class Curve:
    """A curve through input vertices and the Dirichlet data it carries.

    One ``Curve`` is one line of the CLI's curves file (``ifem poisson --curves FILE``); the
    keyword arguments are the line's keywords:

    ==========================================  ============================================
    Python                                      curves-file line
    ==========================================  ============================================
    ``Curve([12, 40, 77], 0.5)``                ``0.5 12 40 77``
    ``Curve([5, 9, 13], 1, closed=True)``       ``closed 1 5 9 13``
    ``Curve([3, 8, 20, 31], 0, bezier=True)``   ``bezier 0 3 8 20 31`` (4 rounds)
    ``Curve([3, 8, 20, 31], [0, 1], bezier=6)`` ``bezier=6 0 1 : 3 8 20 31``
    ``Curve([12, 40, 77], [0, 0.5, 1])``        ``0 0.5 1 : 12 40 77``
    ``Curve([12, 40, 77], left=0, right=1)``    ``slit 0 1 12 40 77``
    ``Curve([12, 77], left=[0, 1],``            ``slit 0 1 : 1 0 : 12 77``
    ``right=[1, 0])``
    ==========================================  ============================================

    Args:
        vertices: ≥ 2 vertex ids (0-based rows of V), no vertex twice in a row: the waypoints of
            a geodesic (the curve passes through each, in order, and may bend there), or the
            control points of a Bézier curve.
        value: the value u takes along the curve: one number (constant), or one per vertex
            (linear in arc length between them; a closed curve closes back to the first value),
            or for a Bézier curve two (at its first and last control point). None: no value (the
            curve can still be used by :func:`curve_distance`, which ignores values).
        closed: a closed geodesic loop through the vertices, back to the first (do not repeat
            the first vertex).
        bezier: a geodesic Bézier curve with ``vertices`` as control points: ``True`` for 4 rounds
            of de Casteljau subdivision, or the number of rounds in [0, 16]. None / False: a
            geodesic through the vertices.
        left, right: make the curve a *slit*: the surface is cut open along it, and u takes
            ``left`` on its left side and ``right`` on its right (each one number or a list, as
            ``value``; as many of each). Left: walking from ``vertices[0]`` towards
            ``vertices[1]``, the left-hand side seen from where the face normals point (the
            side from which ``F``'s corners run counter-clockwise). An end of an open slit
            inside the surface takes the mean of the two sides' values.
        origin: where the curve came from, used in error messages (:func:`read_curves` sets
            ``'file:line'``; solvers name a curve without one ``curves[i]``).

    Curves may meet and cross at vertices (a vertex where values differ takes their mean) but
    may not share an edge. Bad data raises :class:`ifem.InvalidInput` naming the curve: fewer
    than 2 vertices, a vertex twice in a row, a wrong number of values, a value that is not
    finite, rounds out of range. Vertex ids are checked against the mesh when solving.

    Attributes:
        vertices: int64 array of vertex ids.
        value: float64 array of values (length 1: constant) or None; None on a slit.
        left, right: float64 arrays of a slit's values, else None.
        closed, bezier, slit, origin: as given (``bezier``: rounds or None).
        shape: ``'path'``, ``'loop'`` or ``'bezier'``.
    """

    __slots__ = ("vertices", "closed", "bezier", "slit", "origin", "_values", "_right")

    def __init__(self, vertices, value=None, *, closed=False, bezier=None, left=None,
                 right=None, origin=None):
        name = origin or "Curve"
        if (left is None) != (right is None):
            raise InvalidInput(f"{name}: a slit needs both left and right values")
        if left is not None and value is not None:
            raise InvalidInput(f"{name}: give value (a curve) or left and right (a slit), not "
                               "both")
        if bezier is True:
            bezier = 4
        elif bezier is False:
            bezier = None
        if bezier is not None and (isinstance(bezier, (bool, np.bool_))
                                   or not isinstance(bezier, numbers.Integral)
                                   or not 0 <= bezier <= _MAX_ROUNDS):
            raise InvalidInput(f"{name}: bezier must be True or a number of rounds in [0, "
                               f"{_MAX_ROUNDS}], got {bezier!r}")
        if bezier is not None and closed:
            raise InvalidInput(f"{name}: a curve is closed or Bézier, not both")
        self.vertices = _vertex_ids(vertices, name)
        self.closed = bool(closed)
        self.bezier = None if bezier is None else int(bezier)
        self.slit = left is not None
        self.origin = origin
        self._values = _reals(left if self.slit else value, "left" if self.slit else "value",
                              name)
        self._right = _reals(right, "right", name)
        _ifem.check_curve(self._spec(name))

    @classmethod
    def _from_spec(cls, spec):
        vertices, shape, rounds, values, slit, right, origin = spec
        c = cls.__new__(cls)
        c.vertices, c.closed = vertices.astype(np.int64), shape == "loop"
        c.bezier = int(rounds) if shape == "bezier" else None
        c.slit, c.origin = bool(slit), origin
        c._values, c._right = np.array(values, dtype=np.float64), np.array(right, np.float64)
        return c

    @property
    def shape(self):
        return "bezier" if self.bezier is not None else "loop" if self.closed else "path"

    @property
    def value(self):
        return None if self.slit or self._values.size == 0 else self._values

    @property
    def left(self):
        return self._values if self.slit else None

    @property
    def right(self):
        return self._right if self.slit else None

    def _spec(self, origin=None):
        """The tuple the compiled module takes (python/src/bind_curves.cpp)."""
        return (self.vertices, self.shape, 4 if self.bezier is None else self.bezier,
                self._values, self.slit, self._right, self.origin or origin or "Curve")

    def to_line(self):
        """The curve as a line of the CLI's curves file (numbers written to round-trip exactly;
        the library's writer, solvers::curve_line).

        Raises:
            InvalidInput: a curve without values (the file format needs them).
        """
        return _ifem.curve_line(self._spec())

    def __repr__(self):
        args = [repr(self.vertices.tolist())]
        if self.slit:
            args += [f"left={self._values.tolist()!r}", f"right={self._right.tolist()!r}"]
        elif self._values.size:
            v = self._values
            args.append(repr(float(v[0]) if v.size == 1 else v.tolist()))
        if self.closed:
            args.append("closed=True")
        if self.bezier is not None:
            args.append(f"bezier={self.bezier}")
        return f"Curve({', '.join(args)})"

    def __eq__(self, other):
        if not isinstance(other, Curve):
            return NotImplemented
        return (self.shape == other.shape and self.bezier == other.bezier
                and self.slit == other.slit and np.array_equal(self.vertices, other.vertices)
                and np.array_equal(self._values, other._values)
                and np.array_equal(self._right, other._right))


def read_curves(path):
    """Reads a curves file (the format of ``ifem poisson --curves FILE``) into a list of
    :class:`Curve`, each with ``origin = 'path:line'`` for messages.

    One curve per line: optional keywords ``closed`` or ``bezier[=R]`` and ``slit``, then the
    value(s), then the vertex ids (see :class:`Curve` for each form); ``#`` starts a comment.

    Raises:
        IoError: an unreadable file, a malformed line (naming ``path:line`` and the token), or a
            file without curves.
    """
    return [Curve._from_spec(s) for s in _ifem.read_curves_file(os.fspath(path))]


def write_curves(path, curves):
    """Writes curves as a curves file that ``ifem poisson/distance --curves`` and
    :func:`read_curves` read back (same curves, numbers round-trip exactly): the library's
    writer (solvers::write_curves_file), atomic (a temporary file, then renamed).

    Raises:
        InvalidInput: a curve without values.
        IoError: the file cannot be written.
    """
    _ifem.write_curves_file(os.fspath(path), _specs(curves))


def _as_curve(item, i):
    if isinstance(item, Curve):
        return item
    if isinstance(item, dict):
        try:
            return Curve(**{"origin": f"curves[{i}]", **item})
        except TypeError as e:
            raise InvalidInput(f"curves[{i}]: {e} (keys: vertices, value, closed, bezier, left, "
                               "right)") from None
    raise InvalidInput(f"curves[{i}] must be an ifem.Curve or a dict of its arguments, got "
                       f"{type(item).__name__}")


def _as_curves(curves):
    """A curves file's path, one Curve, or a list of Curves / dicts → a list of Curves."""
    if isinstance(curves, (str, os.PathLike)):
        return read_curves(curves)
    if isinstance(curves, (Curve, dict)):
        curves = [curves]
    if not isinstance(curves, (list, tuple)):
        raise InvalidInput("curves must be a list of ifem.Curve (or dicts), one Curve, or a "
                           f"curves file's path; got {type(curves).__name__}")
    return [_as_curve(c, i) for i, c in enumerate(curves)]


def _specs(curves):
    return [c._spec(f"curves[{i}]") for i, c in enumerate(_as_curves(curves))]


def _refine(refine, min_angle, resolution, max_area, max_insertions, conform=True,
            correspondence="integer"):
    if not refine:
        return None
    return (float(min_angle), float(resolution), float(max_area),
            -1 if max_insertions is None else int(max_insertions), bool(conform),
            str(correspondence))


def _flipout_cap(max_iterations):
    """FlipOut's cap as the binding takes it: None → −1 (the library's default, 10 × #E + 1000)."""
    if max_iterations is None:
        return -1
    cap = max_iterations
    if isinstance(cap, (bool, np.bool_)) or not isinstance(cap, (int, np.integer)) or cap < 0:
        raise InvalidInput(f"max_iterations must be an integer ≥ 0 (or None), got {cap!r}")
    return int(cap)


def _dirichlet(dirichlet):
    """None, {vertex: value} or (vertices, values) → (vertices, values) or (None, None)."""
    if dirichlet is None:
        return None, None
    if isinstance(dirichlet, dict):
        return list(dirichlet.keys()), list(dirichlet.values())
    if isinstance(dirichlet, (list, tuple)) and len(dirichlet) == 2:
        return dirichlet[0], dirichlet[1]
    raise InvalidInput("dirichlet must be a dict {vertex: value} or a pair (vertices, values), "
                       f"got {type(dirichlet).__name__}")


def _results(value, lines, info, return_polylines, return_info):
    out = (value,) + ((lines,) if return_polylines else ()) + ((info,) if return_info else ())
    return out if len(out) > 1 else value


def curve_poisson(V, F, curves, rhs=None, dirichlet=None, screening=0.0, refine=False, *,
                  min_angle=25.0, resolution=0.0, max_area=0.0, max_insertions=None,
                  conform=True, mollify=1e-5, max_iterations=None, accept_partial=False,
                  return_polylines=False, return_info=False, correspondence="integer"):
    """Solves (L + c·M) u = M f with u held at the curves' values along them.

    The curves are inserted as constrained edges of the intrinsic Delaunay triangulation
    (FlipOut geodesics through their vertices, Bézier curves), optionally refined without
    crossing them, and u takes each curve's value on every vertex along it (linear in arc
    length between given values, including vertices inserted on the curves). Natural (zero
    Neumann) conditions hold everywhere else, the mesh boundary included. Slits cut the surface
    open: u may jump across them. Same as ``ifem poisson MESH --curves FILE [--rhs]
    [--dirichlet] [--screening c] [--refine] -o OUT.txt``.

    Because the data sits exactly on the curves, linear data is reproduced exactly: on a flat
    square with two straight curves at y = a and y = b held at 0 and 1, u is the piecewise
    linear ramp in y at every vertex (to rounding), whatever the triangulation.

    Args:
        V: #V×3 positions.
        F: #F×3 vertex ids (an edge-manifold, orientable mesh).
        curves: a list of :class:`Curve` (or dicts of Curve's arguments, e.g. ``{'vertices':
            [3, 9], 'value': 1}``), one Curve, or the path of a curves file. Every curve needs a
            value.
        rhs: f, one value per input vertex (None: 0, Laplace's equation); interpolated linearly
            onto vertices inserted on the curves or by refinement.
        dirichlet: more fixed values on input vertices that are not on a curve: a dict
            ``{vertex: value}`` or a pair ``(vertices, values)``.
        screening: c ≥ 0 (screened Poisson).
        refine: constrained intrinsic Delaunay refinement first (curves are split, never
            crossed), with ``min_angle`` (degrees, in (0, 30]), ``resolution`` (also split
            triangles larger than the equilateral one of side resolution × mean edge length; 0:
            no size bound), ``max_area`` (absolute; 0: none) and ``max_insertions`` (None: the
            library's cap), as the CLI's ``--min-angle``, ``--resolution``, ... .
        conform: with refine, split curve and boundary edges whose cotan weight is still
            negative after refinement until every weight is ≥ 0, so that u stays within the
            curves' values (the discrete maximum principle; False: ``--no-conform``).
        correspondence: with refine, how inserted vertices keep their places on the input:
            ``"integer"`` (default; FlipOut's flips and insertions replayed on integer
            coordinates: the same triangulation and values) or ``"signposts"``
            (``--correspondence``).
        mollify: relative mollification margin.
        max_iterations: FlipOut's cap on reroutes while the curves are shortened, all curves
            together (None: 10 × #E + 1000; ``--max-iterations``).
        accept_partial: go on with curves that stopped at that cap (not geodesic yet;
            ``info['flipout']['stopped_by'] == 'iteration cap'``); False raises InvalidInput
            stating what was reached (``--accept-partial``).
        return_polylines: also return the curves as inserted, traced over the input: one
            (#points, 3) array per curve in the order given (a closed curve repeats its first
            point), as ``--curves-out`` writes them.
        return_info: also return a dict: ``dirichlet_vertices`` (vertices held by the curves,
            slit sides counted apart), ``conflicting_vertices`` (where values meet and differ,
            slit tips included: they take the mean), ``slit_copies``, ``flipout`` (FlipOut's
            report), ``bezier_midpoints``, ``curve_lengths``, ``constrained_flips``,
            ``non_delaunay_curve_edges``, ``negative_weights_on_curves`` /
            ``negative_weights_elsewhere``, ``min_weight``, ``vertices`` (of the constrained
            triangulation), ``refined`` (and ``refine``, a summary; ``conforming_splits``,
            ``negative_barrier_weights``: curve and boundary edges whose weight stays negative,
            ``min_relative_barrier_weight``), ``mollify_delta``.

    Returns:
        ``u`` (#V float64, the input's vertices; a vertex on a slit: the mean of its sides), then
        the polylines and the info dict when asked, in that order.

    Raises:
        InvalidInput: a bad curve (named ``curves[i]`` or ``file:line``: vertex out of range,
            fewer than 2 vertices, a wrong number of values, NaN, no value), two curves sharing
            an edge, a Dirichlet vertex on a curve, sizes, bad options; curves FlipOut left at
            ``max_iterations`` without ``accept_partial``.
        NonManifoldInput / InvalidInput: a mesh curves cannot be drawn on (nonmanifold,
            non-orientable, a point cloud).
        IoError: an unreadable curves file.

    Example:
        >>> u = ifem.curve_poisson(V, F, [ifem.Curve([0, 40, 77], 0.0),
        ...                               ifem.Curve([300, 310], left=0, right=1)])
    """
    specs = _specs(curves)
    dv, dval = _dirichlet(dirichlet)
    u, lines, info = _ifem.curve_poisson(
        V, F, specs, rhs, dv, dval, float(screening),
        _refine(refine, min_angle, resolution, max_area, max_insertions, conform,
                correspondence),
        float(mollify), bool(return_polylines), _flipout_cap(max_iterations),
        bool(accept_partial))
    return _results(u, lines, info, return_polylines, return_info)


def curve_distance(V, F, curves, refine=False, *, time_factor=None, correction_steps=None,
                   min_angle=25.0, resolution=0.4, max_area=0.0, max_insertions=None,
                   conform=True, mollify=1e-5, max_iterations=None, accept_partial=False,
                   return_polylines=False, return_info=False, path_bounds=True,
                   correspondence="integer"):
    """Geodesic distance to the nearest curve (heat method on the constrained triangulation).

    Every vertex on a curve is a source, so the distance is exactly 0 along the curves (not
    only at the vertices given). The curves' values and slits do not matter here (a curve may
    have no value). Same as ``ifem distance MESH --curves FILE [--refine] -o OUT.txt``.

    Args:
        V: #V×3 positions.
        F: #F×3 vertex ids (an edge-manifold, orientable mesh).
        curves: as :func:`curve_poisson`.
        refine: the accurate mode, constrained: refine to edges of about ``resolution`` × the
            mean edge length (default 0.4) and ``min_angle``, then the heat method with t =
            0.25·ℓ² and one correction step (``ifem distance --refine``).
        time_factor: m in t = m·h² (None: 1, or 0.25 with refine's size bound).
        correction_steps: φ ← solution of L φ = div(∇φ/|∇φ|), this many times (None: 0, or 1
            when refined with a size bound).
        min_angle, resolution, max_area, max_insertions, conform: refinement settings (see
            :func:`curve_poisson`).
        mollify: relative mollification margin.
        max_iterations, accept_partial: FlipOut's cap on the curves and whether curves left at
            it are accepted (see :func:`curve_poisson`; ``--max-iterations``,
            ``--accept-partial``).
        return_polylines: also return the curves' polylines (as :func:`curve_poisson`).
        return_info: also return a dict (as :func:`curve_poisson`'s, plus ``stages``).
        path_bounds: True (default): values clamped to at most the shortest path along edges
            and across flat diamonds from the curves; False: the heat method's values as
            solved (``--no-path-bounds``).

    Returns:
        ``d`` (#V float64; ``inf`` where no curve reaches), then the polylines and the info
        dict when asked.

    Raises:
        As :func:`curve_poisson` (values are not needed).
    """
    specs = _specs(curves)
    d, lines, info = _ifem.curve_distance(
        V, F, specs,
        _refine(refine, min_angle, resolution, max_area, max_insertions, conform, correspondence),
        None if time_factor is None else float(time_factor),
        None if correction_steps is None else int(correction_steps), float(mollify),
        bool(return_polylines), _flipout_cap(max_iterations), bool(accept_partial),
        _path_bounds(path_bounds))
    return _results(d, lines, info, return_polylines, return_info)


__all__ = ["Curve", "read_curves", "write_curves", "curve_poisson", "curve_distance"]
