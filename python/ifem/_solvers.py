"""Geodesic distance (heat method), Laplace–Beltrami eigenpairs and Poisson problems.

The Python side of ``ifem distance``, ``ifem eigen`` and ``ifem poisson``: the same
preparation (path, mollification, intrinsic Delaunay flips, optional refinement), the same
defaults and the same library calls, so the results are the CLI's to round-off.

Shared conventions:

- Results live on the input's vertices, in the input's order (#V_in values), on every path:
  refinement inserts vertices after the input's and only enriches the discretization.
- ``F=None`` (or an empty F) means a point cloud: the operators come from the k nearest
  neighbours of each point (``knn``), glued into a tufted cover.
- Surface keyword arguments: ``mollify`` (relative mollification margin, in [0, 1]),
  ``path`` (``'auto'``, ``'manifold'``, ``'tufted'`` or ``'pointcloud'``), ``knn``
  (neighbours per point on the point-cloud path, in [2, #points)).
- ``refine=True`` runs intrinsic Delaunay refinement first, tuned by ``min_angle`` (degrees,
  in (0, 30], default 25), ``resolution`` (target edge length as a multiple of the input's
  mean edge length h; 0 = no size bound; default 0.4 for distances, 0 otherwise, as in the
  CLI), ``max_area`` (absolute; 0 = none) and ``max_insertions`` (cap on inserted vertices;
  None: the library's). Changing those without ``refine=True`` raises.
- Everything after ``refine`` is keyword-only.
- Bad arguments raise :class:`ifem.InvalidInput` (a ``ValueError``) naming the argument;
  meshes a requested path cannot represent :class:`ifem.NonManifoldInput`; numerical
  failures :class:`ifem.SolverError` (a ``RuntimeError``).
- Preparation, factorization and every query run with the GIL released: other Python threads
  go on meanwhile, and one :class:`HeatDistanceSolver` may be queried from several threads.
"""

import numbers
import operator

import numpy as np

from . import _ifem
from ._inputs import surface as _input
from ._errors import InvalidInput

# --- argument conversion (every failure an InvalidInput naming the argument) --------------------


def _real(x, name):
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real):
        raise InvalidInput(f"{name} must be a real number, got {type(x).__name__} {x!r}")
    return float(x)


def _int(x, name):
    if isinstance(x, (bool, np.bool_)):
        raise InvalidInput(f"{name} must be an integer, got {x!r}")
    try:
        return operator.index(x)
    except TypeError:
        raise InvalidInput(f"{name} must be an integer, got {type(x).__name__} {x!r}") from None


def _optional(x, name, convert):
    return None if x is None else convert(x, name)


def _faces(F):
    return None if F is None or np.size(F) == 0 else F


def _surface(mollify, path, knn):
    if not isinstance(path, str):
        raise InvalidInput(f"path must be a string ('auto', 'manifold', 'tufted' or "
                           f"'pointcloud'), got {path!r}")
    return _real(mollify, "mollify"), path, _int(knn, "knn")


def _refine(refine, min_angle, resolution, max_area, max_insertions, default_resolution,
            correspondence="integer"):
    """The C++ side's `refine` argument: None, or a dict of the refinement settings."""
    if not isinstance(correspondence, str):
        raise InvalidInput(f"correspondence must be 'signposts' or 'integer', got "
                           f"{correspondence!r}")
    if not refine:
        changed = [name for name, value, default in (
            ("min_angle", min_angle, 25.0), ("resolution", resolution, default_resolution),
            ("max_area", max_area, 0.0), ("max_insertions", max_insertions, None),
            ("correspondence", correspondence, "integer"))
            if not (value is default or value == default)]
        if changed:
            raise InvalidInput(f"{', '.join(changed)} only apply with refine=True")
        return None
    return {"min_angle": _real(min_angle, "min_angle"),
            "resolution": _real(resolution, "resolution"),
            "max_area": _real(max_area, "max_area"),
            "max_insertions": _optional(max_insertions, "max_insertions", _int),
            "correspondence": correspondence}


def _points(points):
    """points as (faces int64 (#P,), barycentric coordinates float64 (#P, 3))."""
    try:
        a = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInput("points must be a sequence of (face, b0, b1, b2) rows") from None
    if a.ndim == 1 and a.size == 4:
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] != 4:
        raise InvalidInput(f"points must be a sequence of (face, b0, b1, b2) rows (shape "
                           f"(#P, 4)), got shape {a.shape}")
    faces = a[:, 0]
    bad = ~(np.isfinite(faces) & (faces == np.round(faces)))
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidInput(f"points[{i}]: the face {faces[i]!r} is not an integer")
    return faces.astype(np.int64), np.ascontiguousarray(a[:, 1:])


def _dirichlet(dirichlet):
    """dirichlet as (ids, values): from None, a dict {vertex: value} or a pair (ids, values)."""
    if dirichlet is None:
        return np.zeros(0, np.int64), np.zeros(0)
    if isinstance(dirichlet, dict):
        return np.array(list(dirichlet.keys())), np.array(list(dirichlet.values()))
    if isinstance(dirichlet, (tuple, list)) and len(dirichlet) == 2:
        ids, values = (np.atleast_1d(np.asarray(x)) for x in dirichlet)
        if ids.shape != values.shape:
            raise InvalidInput(f"dirichlet: {ids.size} vertex ids for {values.size} values "
                               f"(shapes {ids.shape} and {values.shape})")
        return ids, values
    raise InvalidInput("dirichlet must be a dict {vertex: value} or a pair (ids, values), got "
                       f"{type(dirichlet).__name__}")


# --- heat distance ------------------------------------------------------------------------------


class HeatDistanceSolver:
    """Geodesic distance by the heat method, prepared once and queried many times.

    The constructor does what ``ifem distance`` does before its query: it builds the intrinsic
    Delaunay triangulation of the input (manifold path, tufted cover, or point cloud), refines
    it when asked, and factors the heat and Poisson matrices; every
    :meth:`compute_distance` then costs a few back-substitutions (milliseconds on meshes of
    tens of thousands of vertices).

    The method (Crane, Weischedel & Wardetzky 2013): one heat step ``(M + t L) u = δ`` with
    ``t = time_factor · h²`` (h the input's mean edge length), the normalized gradient
    ``X = −∇u/|∇u|``, then ``L φ = div X``, shifted so that the sources are at distance 0.
    Meshes with boundary use the mean of the Neumann and Dirichlet heat solutions. Far from the
    sources, where the heat underflows, the solver continues in stages from the frontier of
    the resolved region. A stray hub (a vertex far beyond the model whose every side is an
    outlier, e.g. one pulled away by a bad scan) is cut loose as ``ifem distance`` and
    :func:`geodesic_distance` do, so it moves nothing else; a query from a vertex or point on
    its star runs on the uncut surface (docs/decisions.md D-360, D-380).

    Args:
        V: #V×3 vertex positions (any real dtype), or a mesh / point-cloud file's path (read
            with its normals, as the CLI reads it; F then None).
        F: #F×3 vertex ids, or None / empty for a point cloud.
        refine: the accurate mode of ``ifem distance --refine``: refine to edges of about
            ``0.4·h`` and 25° first (~10× the vertices), then ``t = 0.25·ℓ²`` (ℓ = 0.4·h) and one
            correction step. Markedly more accurate on sliver meshes; costs more to prepare.
        time_factor: m in ``t = m·h²`` (> 0; default 1, or 0.25 with a refinement size bound).
            Larger is smoother, smaller is sharper but noisier.
        correction_steps: times ``φ ← solution of L φ = div(∇φ/|∇φ|)`` after the heat method
            (≥ 0; default 0, or 1 with a refinement size bound).
        mollify: relative mollification margin, in [0, 1].
        path: ``'auto'``, ``'manifold'`` (raise NonManifoldInput if the mesh cannot take it),
            ``'tufted'`` or ``'pointcloud'`` (use only the vertices).
        knn: neighbours per point on the point-cloud path, in [2, #V).
        normals: optional #V×3 normals of a point cloud (its tangent planes; rows zero or not
            finite: PCA); a file's own normals when V is a path.
        min_angle, resolution, max_area, max_insertions: refinement settings (with
            ``refine=True`` only): corner angle bound in degrees, target edge length as a
            multiple of h (0.4 here, as in the CLI), area bound (absolute; 0: none), cap on
            inserted vertices (None: the library's).
        correspondence: with ``refine=True``: how inserted vertices keep their places on the
            input, ``'integer'`` (default; normal coordinates: exact combinatorics) or
            ``'signposts'``; the same triangulation and results either way (the CLI's
            ``--correspondence``; :func:`ifem.refine`). With ``curves`` too (FlipOut's steps
            replayed on the integer coordinates).
        precision: ``'double'`` (default): every factor in double. ``'mixed'``: the queries read
            the Poisson factor as floats, half its bytes; distances move by at most ~3e-7
            relative (the heat factor stays double). Not faster on a machine where the solves
            are not memory-bound (``BENCHMARKS.md``, "Heat queries"); the CLI's
            ``--mixed-precision``.
        path_bounds: True (default): every distance clamped into bounds the exact geodesic
            distance satisfies (at most the shortest path along edges and across flat
            diamonds, at least the straight line to the nearest vertex source), which never
            makes a value less accurate. False: the heat method's values as solved (the CLI's
            ``--no-path-bounds``; faster for many sources).
        progress: None (default: nothing is reported, nothing printed) or a callable
            ``progress(fraction, stage)``, called during the long stages with the fraction done
            (0 first, non-decreasing, exactly 1 last) and the stage's name (``"refine"`` here;
            ``"heat distances"`` in :meth:`compute_distances`).

    Raises:
        InvalidInput: bad arrays or options (the message names the argument).
        NonManifoldInput: ``path='manifold'`` on a mesh that needs the tufted cover.
        SolverError: a factorization failed (degenerate operators).

    Example:
        >>> solver = ifem.HeatDistanceSolver(V, F)
        >>> d0 = solver.compute_distance(0)            # from vertex 0
        >>> d = solver.compute_distance([0, 57, 300])  # to the nearest of three vertices
        >>> dp = solver.compute_distance(points=[(12, 0.2, 0.3, 0.5)])  # from a point of face 12
    """

    def __init__(self, V, F=None, refine=False, *, time_factor=None, correction_steps=None,
                 mollify=1e-5, path="auto", knn=30, min_angle=25.0, resolution=0.4,
                 max_area=0.0, max_insertions=None, precision="double", normals=None,
                 progress=None, path_bounds=True, solver="direct", correspondence="integer"):
        V, F, normals = _input(V, F, normals)
        self._solver = _ifem.HeatDistanceSolver(
            V, _faces(F), _optional(time_factor, "time_factor", _real),
            _optional(correction_steps, "correction_steps", _int), *_surface(mollify, path, knn),
            _refine(refine, min_angle, resolution, max_area, max_insertions, 0.4, correspondence),
            _precision(precision), normals, progress, _path_bounds(path_bounds),
            _solver(solver))

    def compute_distance(self, sources=None, points=None):
        """Geodesic distance to the nearest source, on every input vertex.

        Give exactly one of ``sources`` and ``points``.

        Args:
            sources: a vertex id, or a sequence / 1-D integer array of vertex ids (0-based ids of
                the input, each used by some face). With several, the value is the distance to
                the nearest one, and every source is exactly 0.
            points: surface points ``(face, b0, b1, b2)``, a sequence of them or a #P×4 array:
                ``face`` a row of the input's ``F``, ``b0, b1, b2`` barycentric coordinates of
                its corners ``F[face, 0], F[face, 1], F[face, 2]`` (≥ 0, summing to 1). They are
                located on the solver's (flipped, maybe refined) triangulation by tracing along
                its signposts, or, refined with integer coordinates, through the common
                subdivision (built on the first such query), so they need an edge-manifold,
                orientable mesh: on the tufted and point-cloud paths they raise InvalidInput.

        Returns:
            #V_in float64 array: distances in the unit of V's coordinates, in the input's
            vertex order; ``inf`` where no source reaches (another connected component, vertices
            used by no face).

        Raises:
            InvalidInput: an id out of range, an empty source list, a non-integer dtype, both or
                neither of sources and points, a bad point.
            SolverError: the result is not finite where a source reaches (degenerate input).
        """
        if (sources is None) == (points is None):
            raise InvalidInput("give exactly one of sources (vertex ids) and points "
                               "((face, b0, b1, b2) rows)")
        if points is None:
            return self._solver.compute_distance(sources)
        faces, bary = _points(points)
        return self._solver.compute_distance_from_points(faces, bary)

    def compute_distances(self, sources, progress=None):
        """Geodesic distances from each source on its own: a distance matrix.

        Column ``j`` equals ``compute_distance(sources[j])`` up to rounding (~1e-14 relative),
        but the solves of up to 32 sources share each pass over the factors, so a source costs
        a fraction of a separate query (``BENCHMARKS.md``, "Batched sources"). The CLI's
        ``ifem distance MESH --sources-batch FILE``.

        Args:
            sources: a sequence / 1-D integer array of vertex ids (0-based ids of the input, each
                used by some face); repeats give equal columns.
            progress: None or a callable ``progress(fraction, stage)``: stage
                ``"heat distances"``, the fraction of the sources done, after each block of up to
                32 (0 first, exactly 1 last). Nothing is printed either way.

        Returns:
            #V_in × k float64 array (Fortran order), column j the distances from
            ``sources[j]``, in the input's vertex order; ``inf`` where that source does not
            reach.

        Raises:
            InvalidInput: an id out of range or unreferenced (naming its position), an empty
                list, a non-integer dtype.
        """
        return self._solver.compute_distances(sources, progress)

    @property
    def n_input_vertices(self):
        """#V_in: the input's vertex count (the length of every result)."""
        return self._solver.n_input_vertices

    @property
    def last_query_seconds(self):
        """Seconds the library spent on the latest :meth:`compute_distance` (the back-
        substitutions, restriction to the input and, for points, locating them), without the
        Python call around it; 0 before the first query."""
        return self._solver.last_query_seconds

    @property
    def info(self):
        """dict of what preparation chose and did: ``path``, ``reason``, ``flips``,
        ``mollify_delta``, ``dropped_faces``, ``reoriented_faces``, ``unreferenced_vertices``,
        ``input_vertices``, ``vertices`` / ``faces`` (of the triangulation
        solved on), ``refined``, ``inserted_vertices``, ``signposts`` (refined with signposts),
        ``correspondence`` (``'integer'``, ``'signposts'`` or None), ``mean_edge_length``
        (h of the input), ``target_edge_length`` (ℓ with a refinement size bound, else 0),
        ``time_factor``, ``correction_steps``, ``step_length`` (the h in t = m·h²; 0 when
        computed from the triangulation, e.g. point clouds), ``time_step`` (t, in the solver's
        length unit, a power of two near h) and ``stray_hubs_cut`` (True when vertices far
        beyond the model, all of whose sides are outliers, were cut loose as
        :func:`geodesic_distance` does: docs/decisions.md D-360, D-380)."""
        return self._solver.info

    def __repr__(self):
        i = self.info
        return (f"HeatDistanceSolver({i['input_vertices']} input vertices, path={i['path']!r}, "
                f"refined={i['refined']}, time_factor={i['time_factor']:g}, "
                f"correction_steps={i['correction_steps']})")


def _solver(solver):
    """The linear solver's name, 'direct', 'multigrid' or 'auto' (checked here: the message names
    the argument)."""
    if solver not in ("direct", "multigrid", "auto"):
        raise InvalidInput(f"solver must be 'direct', 'multigrid' or 'auto', got {solver!r}")
    return solver


def _precision(precision):
    """The query precision, 'mixed' or 'double' (checked here: the message names the argument)."""
    if precision not in ("mixed", "double"):
        raise InvalidInput(f"precision must be 'mixed' or 'double', got {precision!r}")
    return precision


def _path_bounds(path_bounds):
    """path_bounds as a bool (checked here: numpy bools pass, other values are refused)."""
    if path_bounds is not True and path_bounds is not False and not isinstance(path_bounds,
                                                                                np.bool_):
        raise InvalidInput(f"path_bounds must be True or False, got {path_bounds!r}")
    return bool(path_bounds)


def distance(V, F=None, sources=None, *, points=None, refine=False, time_factor=None,
             correction_steps=None, mollify=1e-5, path="auto", knn=30, min_angle=25.0,
             resolution=0.4, max_area=0.0, max_insertions=None, precision="double",
             normals=None, curves=None, progress=None, path_bounds=True, solver="direct",
             correspondence="integer"):
    """Geodesic distance from vertices (or surface points) in one call, as ``ifem distance``
    (``heat_distance`` is its deprecated old name).

    Same arguments and result as ``HeatDistanceSolver(V, F, ...).compute_distance(sources,
    points)`` (see :class:`HeatDistanceSolver`); build the solver instead when you ask for
    several distances on the same surface: preparation and factorization dominate the cost.

    With ``curves`` (the CLI's ``--curves``): the distance to the curves instead of to
    sources, :func:`curve_distance` (a list of :class:`Curve` or a curves file's path).

    ``progress``: None or a callable ``progress(fraction, stage)``, told how refinement
    (``refine=True``: stage ``"refine"``) goes; ignored with ``curves``.

    ``path_bounds``: True (default) clamps every value into bounds the exact distance
    satisfies; False returns the heat method's values as solved (the CLI's
    ``--no-path-bounds``); see :class:`HeatDistanceSolver`.

    ``solver``: the linear solver, as the CLI's ``--solver``: ``"direct"`` (Cholesky factors,
    the default), ``"multigrid"`` (conjugate gradients with V-cycles on a hierarchy of coarser
    intrinsic simplifications, see :func:`simplify`; the heat method then continues in stages
    from the frontier of the heat it resolves, each a direct solve on a band around it) or
    ``"auto"`` (the direct solver for distances).

    Returns:
        #V_in float64 array of distances (``inf`` where no source reaches).
    """
    V, F, normals = _input(V, F, normals)
    if curves is not None:
        if sources is not None or points is not None:
            raise InvalidInput("give sources, points or curves, not several (the CLI's --source, "
                               "--curves)")
        from ._curves import curve_distance
        return curve_distance(V, F, curves, refine, time_factor=time_factor,
                              correction_steps=correction_steps, min_angle=min_angle,
                              resolution=resolution, max_area=max_area,
                              max_insertions=max_insertions, mollify=mollify,
                              path_bounds=path_bounds, correspondence=correspondence)
    refine_arg = _refine(refine, min_angle, resolution, max_area, max_insertions, 0.4,
                         correspondence)
    t = _optional(time_factor, "time_factor", _real)
    c = _optional(correction_steps, "correction_steps", _int)
    surface = _surface(mollify, path, knn)
    if (sources is None) == (points is None):
        raise InvalidInput("give exactly one of sources (vertex ids) and points "
                           "((face, b0, b1, b2) rows)")
    if points is not None:
        faces, bary = _points(points)  # checked before the work
        solver = _ifem.HeatDistanceSolver(V, _faces(F), t, c, *surface, refine_arg,
                                          _precision(precision), normals, progress,
                                          _path_bounds(path_bounds), _solver(solver))
        return solver.compute_distance_from_points(faces, bary)
    return _ifem.heat_distance(V, _faces(F), sources, t, c, *surface, refine_arg,
                               _precision(precision), normals, progress,
                               _path_bounds(path_bounds), _solver(solver))


#: Deprecated: the old name of :func:`distance`.
heat_distance = distance


# --- eigenpairs ---------------------------------------------------------------------------------


def eigen(V, F=None, k=10, refine=False, *, mollify=1e-5, path="auto", knn=30, min_angle=25.0,
          resolution=0.0, max_area=0.0, max_insertions=None, return_info=False, normals=None,
          progress=None, correspondence="integer", coarse=0, coarse_iterations=0):
    """The k smallest Laplace–Beltrami eigenpairs ``L φ = λ M φ``, as ``ifem eigen``.

    L is the intrinsic Delaunay cotan Laplacian (positive semi-definite), M the lumped mass;
    solved by shift-invert Lanczos with a sparse Cholesky factor.

    Args:
        V: #V×3 vertex positions.
        F: #F×3 vertex ids, or None / empty for a point cloud.
        k: number of eigenpairs, in [1, #V).
        refine: intrinsic Delaunay refinement first (``min_angle``; ``resolution`` defaults to 0
            here, i.e. angles only): λ and φ are those of the refined triangulation, φ reported
            on the input's vertices.
        mollify, path, knn, min_angle, resolution, max_area, max_insertions, normals,
            correspondence: as in :class:`HeatDistanceSolver` (V may be a file's path there
            too).
        return_info: also return a dict about the preparation (as
            :attr:`HeatDistanceSolver.info`, without the heat-method entries).
        progress: None (default: nothing is reported, nothing printed) or a callable
            ``progress(fraction, stage)``, called during the long stages with the fraction done
            (0 first, non-decreasing, exactly 1 last) and the stage's name (``"refine"`` with
            ``refine=True``, then ``"eigenpairs"``: the Lanczos solves done over an estimate).
        coarse: 0 (exact pairs) or N in (k + 6, #V): spectral coarsening, as ``ifem eigen
            --coarse N``: the surface is simplified to N vertices, the coarse pairs prolonged as
            a subspace and Rayleigh–Ritz with the fine L, M gives approximate pairs (each λ
            above the exact one; ``info["eigen_residuals"]`` the relative residuals
            ``‖Lφ − λMφ‖ / ‖λMφ‖``, ``info["eigen_coarse_vertices"]`` N).
        coarse_iterations: with ``coarse``: block iterations ``X ← (L − σM)⁻¹ M X`` with one
            fine Cholesky factor refining the subspace toward the exact pairs (0: none).

    Returns:
        ``evals`` (k,) ascending, in 1 / length² units (λ ≥ 0 up to round-off; λ = 0 once per
        connected component, with a constant φ), and ``evecs`` (#V_in, k), column j the
        eigenvector of ``evals[j]``: M-orthonormal on the triangulation solved on
        (``Σ_i M_ii φ_a(i) φ_b(i) = δ_ab`` when not refined), sign arbitrary, 0 on vertices
        used by no face. And ``info`` when asked.

        On the unit sphere the exact eigenvalues are ``l(l + 1)``, each ``2l + 1`` times.

    Raises:
        InvalidInput: bad arrays or options, k out of range.
        SolverError: Lanczos did not converge, or the factorization failed.
    """
    V, F, normals = _input(V, F, normals)
    evals, evecs, info = _ifem.eigen(V, _faces(F), _int(k, "k"), *_surface(mollify, path, knn),
                                     _refine(refine, min_angle, resolution, max_area,
                                             max_insertions, 0.0, correspondence), normals,
                                     progress, _int(coarse, "coarse"),
                                     _int(coarse_iterations, "coarse_iterations"))
    return (evals, evecs, info) if return_info else (evals, evecs)


# --- Poisson ------------------------------------------------------------------------------------


def poisson(V, F=None, rhs=None, dirichlet=None, screening=0.0, refine=False, *, mollify=1e-5,
            path="auto", knn=30, min_angle=25.0, resolution=0.0, max_area=0.0,
            max_insertions=None, return_info=False, normals=None, curves=None, progress=None,
            solver="direct", correspondence="integer"):
    """Solves ``−Δu + c·u = f`` with Dirichlet values on chosen vertices, as ``ifem poisson``.

    Discretely ``(L + c M) u = M f`` (L the intrinsic Delaunay cotan Laplacian, positive
    semi-definite; M the lumped mass), with u fixed on the Dirichlet vertices and natural (zero
    Neumann) conditions everywhere else, the mesh boundary included.

    Without Dirichlet data and with ``screening == 0``, each connected component is pure
    Neumann: f is made compatible by removing its mass-weighted mean there, and the zero-mean
    solution (``Σ_i M_ii u_i = 0``) is returned. Vertices used by no face get 0 (or their
    Dirichlet value).

    Args:
        V: #V×3 vertex positions.
        F: #F×3 vertex ids, or None / empty for a point cloud.
        rhs: f, one finite value per input vertex (#V_in); None for 0 (Laplace's equation).
            f is a density (per unit area): the solver multiplies it by the mass.
        dirichlet: the prescribed values: a dict ``{vertex: value}`` or a pair
            ``(ids, values)`` of equal-length sequences; ids distinct, in [0, #V_in); values
            finite. None: no Dirichlet vertex.
        screening: c ≥ 0, in 1 / length² units (0: plain Poisson).
        refine: intrinsic Delaunay refinement first (needs an edge-manifold, orientable mesh:
            f is interpolated linearly onto the inserted vertices); ``resolution`` defaults to 0.
        mollify, path, knn, min_angle, resolution, max_area, max_insertions, normals,
            correspondence: as in :class:`HeatDistanceSolver` (V may be a file's path there
            too).
        return_info: also return a dict about the preparation.
        curves: the CLI's ``--curves``: u held at the curves' values along them,
            :func:`curve_poisson` (a list of :class:`Curve` or a curves file's path).
        progress: None (default: nothing is reported, nothing printed) or a callable
            ``progress(fraction, stage)``, told how refinement goes (``refine=True``: stage
            ``"refine"``; 0 first, non-decreasing, exactly 1 last); ignored with ``curves``.
        solver: ``"direct"`` (default), ``"multigrid"`` or ``"auto"``, as in :func:`distance`
            (the CLI's ``--solver``).

    Returns:
        u, #V_in float64 array in the input's vertex order (and ``info`` when asked).

    Raises:
        InvalidInput: rhs of the wrong length or with a NaN / inf, bad Dirichlet data (an id out
            of range or repeated, a non-finite value, ids and values of different lengths), a
            negative screening, bad options; refinement on a mesh without a correspondence
            (the tufted cover).
        SolverError: the factorization failed.
    """
    V, F, normals = _input(V, F, normals)
    if curves is not None:
        from ._curves import curve_poisson
        return curve_poisson(V, F, curves, rhs, dirichlet, screening, refine, min_angle=min_angle,
                             resolution=resolution, max_area=max_area,
                             max_insertions=max_insertions, mollify=mollify,
                             return_info=return_info, correspondence=correspondence)
    ids, values = _dirichlet(dirichlet)
    u, info = _ifem.poisson(V, _faces(F), rhs, ids, values, _real(screening, "screening"),
                            *_surface(mollify, path, knn),
                            _refine(refine, min_angle, resolution, max_area, max_insertions,
                                    0.0, correspondence), normals, progress, _solver(solver))
    return (u, info) if return_info else u


__all__ = ["HeatDistanceSolver", "distance", "heat_distance", "eigen", "poisson"]
