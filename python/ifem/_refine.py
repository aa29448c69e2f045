"""Intrinsic Delaunay refinement of a triangle mesh (the Python side of ``ifem refine``).

Refinement improves the *triangulation* without touching the *surface*: new vertices are
inserted on the input's triangles (circumcenters of bad triangles, Chew's second algorithm, as
in Sharp, Soliman & Crane 2019, "Navigating Intrinsic Triangulations") and edges are flipped,
until every triangle has all its corner angles above a bound. The refined triangles are
*intrinsic*: their edges are geodesics drawn on the input surface, not straight 3D segments,
so they bend over the input's edges. Signposts record where every inserted vertex lies on
the input, which gives its 3D position, a way to carry data from the input's vertices onto it,
and the common subdivision (the overlay of both triangulations) for display.
"""

import os

import numpy as np

from . import _ifem
from ._errors import InvalidInput
from ._inputs import surface as _input
from ._operators import _csc, _diag


class RefinedTriangulation:
    """An intrinsic triangulation refined over an input mesh; made by :func:`refine` or
    :func:`load_refined`, not constructed directly.

    Vertex ids: the input's vertices keep their ids ``0 .. n_input_vertices - 1``; the vertices
    refinement inserted come after them, ``n_input_vertices .. n_vertices - 1``. So a result
    computed on the refined triangulation (a solution of ``L u = M f``, an eigenvector)
    restricted to the input is its first ``n_input_vertices`` entries (:meth:`to_input`), and
    data given on the input is carried onto the refined triangulation by :meth:`from_input`.

    Lengths are in the unit of the input's coordinates (areas in its square); the surface, its
    total area and its geodesic distances are those of the input mesh (after mollification,
    which adds at most a tiny length to every edge of nearly degenerate triangles).

    Attributes:
        n_input_vertices: #V_in, the input's vertex count.
        n_vertices: #V ≥ #V_in, vertices of the refined triangulation.
        n_faces: #F, triangles of the refined triangulation.
        report: dict of what refinement did (see :func:`refine`), or None after
            :func:`load_refined` (the file holds the triangulation, not its history).
    """

    def __init__(self, handle):
        self._h = handle

    @property
    def n_input_vertices(self):
        """#V_in: the input's vertices, ids ``0 .. n_input_vertices - 1`` here too."""
        return self._h.n_input_vertices

    @property
    def n_vertices(self):
        """#V: vertices of the refined triangulation, input and inserted."""
        return self._h.n_vertices

    @property
    def n_faces(self):
        """#F: triangles of the refined triangulation."""
        return self._h.n_faces

    @property
    def correspondence(self):
        """``"signposts"`` or ``"integer"``: how the inserted vertices keep their places on the
        input (``refine(..., correspondence=)``; a loaded file's own)."""
        return self._h.correspondence

    @property
    def report(self):
        """What refinement did, as a dict (a copy; keys listed in :func:`refine`), or None for
        a triangulation made by :func:`load_refined`."""
        r = self._h.report
        return None if r is None else dict(r)

    def positions(self):
        """3D positions of every vertex of the refined triangulation, on the input surface.

        Input vertices are at their own positions (rows ``0 .. n_input_vertices - 1`` equal
        ``V``); an inserted vertex is at its place on an input triangle (barycentric
        interpolation of its corners). The same positions as ``ifem refine --mesh`` writes.

        Returns:
            #V×3 float64 array.
        """
        return self._h.positions()

    def faces(self):
        """The refined intrinsic triangles, as vertex ids into :meth:`positions`.

        Drawing ``positions(), faces()`` as a flat-shaded 3D mesh shows the connectivity only
        approximately: each intrinsic edge is a geodesic *on* the input surface, which can bend
        across input edges (:meth:`common_subdivision` draws the exact overlay). Consistently
        oriented as the input.

        Returns:
            #F×3 int32 array.
        """
        return self._h.faces()

    def edge_lengths(self):
        """Intrinsic side lengths of every refined triangle (geodesic lengths on the input).

        ``l[f, k]`` is the length of the side from ``faces()[f, k]`` to
        ``faces()[f, (k + 1) % 3]``; with them the corner angles follow from the law of
        cosines. In the input's length unit; generally *not* the 3D distance between
        ``positions()`` of the endpoints (edges bend over the input's edges).

        Returns:
            #F×3 float64 array.
        """
        return self._h.edge_lengths()

    def laplacian(self):
        """The cotan Laplacian ``L`` and lumped mass ``M`` of the refined triangulation.

        Same conventions as :func:`ifem.laplacian` (``L`` symmetric positive semi-definite,
        ``L @ 1 == 0``, off-diagonals ≤ 0 as the triangulation is intrinsic Delaunay), but on
        all #V vertices: refined triangles have no small angles, so ``L`` is well conditioned.
        ``M.sum()`` is the input's total area.

        Returns:
            ``L, M``: scipy.sparse.csc_matrix, #V×#V.
        """
        parts, m = self._h.laplacian()
        return _csc(parts), _diag(m)

    def common_subdivision(self):
        """The overlay of the refined and the input triangulations, as a 3D triangle mesh.

        Every intersection of a refined triangle with an input triangle (a convex polygon) is
        fanned into triangles; drawn, the mesh shows the intrinsic edges exactly where they run
        on the input surface. Its total area is the input's. The same mesh and face properties
        as ``ifem refine MESH -o OUT.ply`` writes.

        Returns:
            ``V`` (#Vs×3 float64: the input's vertices first with the same ids, then inserted
            vertices, then crossings of intrinsic and input edges), ``F`` (#Fs×3 int32),
            ``intrinsic_face`` (#Fs int32: the refined triangle, an index into :meth:`faces`,
            each face lies in) and ``input_face`` (#Fs int32: the input triangle, a row of the
            ``F`` given to :func:`refine`).

        Raises:
            InvalidInput: over the memory budget given to :func:`refine`.
            TraceError: an intrinsic edge could not be traced (degenerate input).
        """
        return self._h.common_subdivision()

    def to_input(self, x):
        """Per-vertex data on the refined triangulation restricted to the input's vertices.

        Args:
            x: array with #V rows (a vector, or #V×k for several functions).

        Returns:
            Its first #V_in rows (a view, not a copy), in the input's vertex order.

        Raises:
            InvalidInput: x does not have #V rows.
        """
        a = np.asarray(x)
        if a.ndim == 0 or a.shape[0] != self.n_vertices:
            raise InvalidInput(f"x must have one row per vertex of the refined triangulation "
                               f"({self.n_vertices}), got shape {a.shape}")
        return a[:self.n_input_vertices]

    def from_input(self, x):
        """Per-vertex data given on the input's vertices, carried onto every refined vertex.

        Input vertices keep their values; an inserted vertex gets the linear interpolation of
        the values at the corners of the input triangle it lies on (exact for functions linear
        on each input triangle: the piecewise-linear function on the input is unchanged).

        Args:
            x: #V_in values, or #V_in×k (each column carried over).

        Returns:
            #V float64 array (#V×k for a 2-D x).

        Raises:
            InvalidInput: wrong number of rows, a non-finite or non-numeric value.
        """
        a = np.asarray(x)
        if a.ndim == 2:
            if a.shape[0] != self.n_input_vertices:
                raise InvalidInput(f"x must have one row per input vertex "
                                   f"({self.n_input_vertices}), got shape {a.shape}")
            cols = [self._h.from_input(np.ascontiguousarray(a[:, j])) for j in range(a.shape[1])]
            return np.stack(cols, axis=1) if cols else np.zeros((self.n_vertices, 0))
        return self._h.from_input(a)

    def traced_edges(self):
        """The intrinsic edges traced over the input surface (through the integer coordinates or
        the signposts, :attr:`correspondence`): one k×3
        array of 3D points per intrinsic edge (edge order), from one endpoint to the other,
        every point on a face of the input (its crossings of the input's edges in between) —
        the lines :func:`view` draws with ``triangulation=``, as ``ifem refine --lines`` writes.

        Raises:
            TraceError: a trace failed (a degenerate input).
        """
        return _ifem.traced_edges(self._h)

    def save(self, path):
        """Saves the input and the refined triangulation (gluing, lengths, and normal
        coordinates with roundabouts and spokes, or signposts with inserted vertices' places) to
        a text file, format ``ifem-integer 1`` or ``ifem-signpost 1`` (as ``ifem refine
        --save``);
        every number with 17 digits, so :func:`load_refined` restores it bit for bit.

        Args:
            path: the file to write (str or os.PathLike; atomically: temporary file, rename).

        Raises:
            IoError: the file cannot be written.
        """
        self._h.save(os.fspath(path))

    def __repr__(self):
        s = (f"RefinedTriangulation(n_input_vertices={self.n_input_vertices}, "
             f"n_vertices={self.n_vertices}, n_faces={self.n_faces}")
        r = self._h.report
        if r is not None:
            after = r["min_angle_after_excluding_needles"]
            if r["relax"] is not None:  # relaxation's edge splits may have lowered it
                after = r["relax"]["min_angle_after"]
            s += f", min_angle={r['min_angle_before']:.3f}° -> {after:.3f}°"
            if r["hit_insertion_cap"]:
                s += ", stopped at the insertion cap"
        return s + ")"


def refine(V, F=None, min_angle=25, resolution=0, max_area=0, max_insertions=None, relax=0,
           max_edge=0, mollify=1e-5, memory_budget=None, progress=None,
           correspondence="integer"):
    """Intrinsic Delaunay refinement: a triangulation of the same surface with good angles.

    The mesh is made intrinsic Delaunay by edge flips, then vertices are inserted at the
    circumcenters of bad triangles, located on the surface by tracing straight lines over it
    (Chew's second algorithm; integer coordinates or signposts keep their places), until
    every triangle has all corner angles ≥
    ``min_angle`` and, with a size bound, is small enough. The surface never changes: inserted
    vertices lie on the input's triangles and the total area is the input's. Input vertices
    keep their ids ``0 .. #V_in - 1``; inserted vertices follow. Equivalent to ``ifem refine``
    with the same options.

    Triangles whose small angle sits at a cone vertex whose total angle is below the bound
    (twice the bound inside) cannot be fixed; they are left alone and counted
    (``report['needle_faces']``). Boundary edges facing obtuse angles are split too, so the
    refined Laplacian has non-negative weights everywhere.

    Args:
        V: #V_in×3 positions, or a mesh file's path (F then None), as ``ifem refine MESH``.
        F: #F_in×3 vertex ids of an edge-manifold, orientable mesh, with or without boundary.
        min_angle: smallest corner angle wanted, degrees, in (0, 30].
        resolution: also refine until edges are about ``resolution × h`` long (h: the input's
            mean edge length): triangles larger than the equilateral one of that side are
            split. 0: no size bound.
        max_area: also split triangles of area above this (absolute, in the input's squared
            length unit). 0: no bound.
        max_insertions: stop after this many inserted vertices (``report['hit_insertion_cap']``
            says so). None: 10 × #V_in + 2000, plus 4 × area / (max area) with a size bound.
        relax: passes of optimal Delaunay (ODT) relaxation of the inserted vertices afterwards,
            each moving them inside their flat star on the surface (input vertices never move;
            the minimum angle is kept).
        max_edge: with ``relax``: after each pass split edges longer than this (absolute
            length). 0: no bound.
        mollify: relative mollification margin (as in :func:`ifem.laplacian`).
        memory_budget: gigabytes; a request whose estimated memory (about 4 KiB per vertex)
            exceeds it is refused up front, and insertion stops there; the common subdivision
            is held to it too. None: half the physical memory (or 80% of ``ulimit -v``).
        progress: None (default: nothing is reported, nothing printed) or a callable
            ``progress(fraction, stage)``, stage ``"refine"``: the insertions made over their
            estimate (0 first, non-decreasing, exactly 1 last).
        correspondence: how inserted vertices keep their places on the input, as ``ifem
            refine --correspondence``: ``"integer"`` (default: normal coordinates, so the
            common subdivision's combinatorics are exact integers and it partitions the input's
            faces on every mesh tried) or ``"signposts"`` (directions traced in floating point;
            on a few near-degenerate meshes their overlay does not cover the input faces
            exactly; for comparison with earlier results). Both give the same triangulation
            (same insertions, same lengths); docs/decisions.md D-330.

    Returns:
        A :class:`RefinedTriangulation`, whose ``report`` dict holds:

        - ``vertices_before``, ``vertices_after``, ``insertions`` (vertices inserted: the
          ``face_insertions`` (circumcenters), ``edge_splits`` and ``boundary_splits``);
          ``relax`` may split more (``n_vertices`` counts all);
        - ``flips``, ``failed_traces``;
        - ``hit_insertion_cap`` (stopped by ``max_insertions`` or the memory budget, with
          ``bad_faces_left`` triangles still below the bounds), ``needle_faces`` (left alone),
          ``scale_floor_faces`` (bad triangles left where insertions were cascading, counted in
          ``bad_faces_left``; only above about 26.5°);
        - smallest corner angles in degrees: ``min_angle_input`` (the input triangles),
          ``min_angle_before`` (their intrinsic Delaunay triangulation), ``min_angle_after``
          and ``min_angle_after_excluding_needles`` (the result);
        - ``input_mean_edge_length`` (h), ``target_edge_length`` (resolution × h; 0 without),
          ``mollify_delta`` (the length mollification added to every edge; usually 0);
        - ``seconds`` (the whole call), ``relax`` (the relaxation's counts and angles as a
          dict, or None) and ``summary`` (one line for people).

    Raises:
        InvalidInput: bad arrays, an option out of range (the message names it), no faces, or
            an estimate over the memory budget.
        NonManifoldInput: a nonmanifold mesh (an edge with 3+ faces; NonOrientableInput for a
            non-orientable one): refinement needs integer coordinates or signposts, which the
            tufted cover these take
            in :func:`ifem.laplacian` does not have.
    """
    mi = None if max_insertions is None else _int(max_insertions, "max_insertions")
    mb = None if memory_budget is None else float(memory_budget)
    V, F, _ = _input(V, F)
    if not isinstance(correspondence, str):
        raise InvalidInput(f"correspondence must be 'signposts' or 'integer', got "
                           f"{correspondence!r}")
    return RefinedTriangulation(_ifem.refine(
        V, F, float(min_angle), float(resolution), float(max_area), mi, _int(relax, "relax"),
        float(max_edge), float(mollify), mb, correspondence, progress))


def load_refined(path):
    """Loads a refined triangulation saved by :meth:`RefinedTriangulation.save` (or by
    ``ifem refine --save``): the same vertices, faces, lengths and places on the input, so the
    same positions, faces, common subdivision and Laplacian, bit for bit. Its ``report`` is None.

    Raises:
        IoError: a missing file, or one that is not a valid ``ifem-signpost 1`` or
            ``ifem-integer 1`` file (the message names the line).
    """
    return RefinedTriangulation(_ifem.load_refined(os.fspath(path)))


def _int(x, name):
    """x as an int, refusing non-integral values (2.5 passes) with InvalidInput naming it."""
    try:
        i = int(x)
        if i == x:
            return i
    except (TypeError, ValueError, OverflowError):
        pass
    raise InvalidInput(f"{name} must be an integer, got {x!r}")


def transfer(refined, x, method="l2", back=False):
    """Carries a function given by per-vertex values (linear on each triangle) from the input
    mesh onto a refined triangulation, or with ``back=True`` from it back onto the input.
    Equivalent to ``ifem transfer`` with the same refinement.

    Methods:
        ``"pointwise"``: each target vertex takes the function's value at its place (inserted
        vertices interpolate the input triangle they lie on, as
        :meth:`RefinedTriangulation.from_input`; back, input vertices keep their values, as
        :meth:`RefinedTriangulation.to_input`).
        ``"l2"``: Galerkin projection: the target ``u`` minimises ∫ (u − f)² dA, solving
        ``M u = M_mixed f`` with the target's consistent mass matrix and the mixed mass matrix
        integrated exactly over the common subdivision. Keeps ∫ f dA and reproduces functions
        linear on both triangulations (a linear function on a flat mesh).

    Args:
        refined: a :class:`RefinedTriangulation` (:func:`refine`, :func:`load_refined`).
        x: #V_in values on the input's vertices, or with ``back=True`` #V values on the
            refined triangulation's vertices; finite.
        method: ``"pointwise"`` or ``"l2"``.
        back: False: input → refined (returns #V values, the first #V_in on the input's
            vertices); True: refined → input (returns #V_in values, input order).

    Returns:
        float64 array.

    Raises:
        InvalidInput: wrong length, a non-finite value, an unknown method.
        SolverError: the mass matrix solve did not converge (degenerate triangles).
    """
    if not isinstance(refined, RefinedTriangulation):
        raise InvalidInput("refined must be a RefinedTriangulation (ifem.refine or "
                           f"ifem.load_refined), got {type(refined).__name__}")
    return _ifem.transfer(refined._h, x, str(method), bool(back))


__all__ = ["refine", "load_refined", "RefinedTriangulation", "transfer"]
