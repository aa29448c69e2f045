"""Tangent fields: the smoothest n-direction field (vectors, lines, crosses), free or aligned
(``ifem field``), and the Vector Heat Method's parallel transport and logarithmic map (``ifem
transport``, ``ifem logmap``)."""

import numpy as np

from . import _ifem
from ._curves import _flipout_cap, _specs
from ._errors import InvalidInput
from ._inputs import surface as _input


def field(V, F=None, symmetry=1, align_boundary=False, constraint_vertices=None,
          directions=None, mollify=1e-5, return_info=False, *, normals=None, path="auto", knn=30,
          curves=None, max_iterations=None, accept_partial=False):
    """The smoothest n-direction field on a mesh or point cloud, as unit 3D tangent vectors per
    vertex (``direction_field`` is its deprecated old name).

    The field is the smallest eigenvector of the connection Laplacian of the intrinsic
    Delaunay triangulation (Knöppel, Crane, Pinkall, Schröder 2013), or, with constraints, the
    smoothest field through them (harmonic in the power representation). Each connected
    component without a constraint gets its own smoothest field (a triangle soup works: one
    per piece); a component without area in space has no tangent plane and gets no field
    (vectors 0). Same as
    ``ifem field MESH --symmetry N [--align-boundary] [--constraints FILE] [--curves FILE]``.
    On nonmanifold or non-orientable meshes (the tufted path) and point clouds the connection
    comes from per-vertex 3D frames: normals from the faces (or ``normals``, else PCA of the
    neighbours), oriented consistently by propagation, and the minimal rotation between
    neighbours' normals.

    With ``curves``, the field conforms to curves drawn through the mesh's vertices (the
    thesis' Figure 10 left): they are inserted as edges of a constrained intrinsic Delaunay
    triangulation exactly as for :func:`curve_poisson` (FlipOut geodesics, Bézier curves), and
    the field is held along them at every vertex on them (inside a curve, the mean of the edge
    leaving and the continuation of the edge arriving, in the n-th power; for n = 1 the vectors
    point the way the curve runs). On a flat mesh, a loop through equally spaced vertices of a
    circle gives a field exactly tangent to the circle there.

    Args:
        V: #V×3 positions, or a file's path (read with its normals, as the CLI reads it).
        F: #F×3 vertex ids; ``None`` (or empty) for a point cloud.
        symmetry: n ≥ 1 — 1 vectors, 2 lines, 4 crosses.
        align_boundary: hold the field along the boundary (meshes; not point clouds); at a corner
            along both sides when ``symmetry`` allows it (a cross at 90° or 270°), else along the
            ``symmetry``-direction mean of the two sides.
        constraint_vertices: vertex ids where a direction is held (with ``directions``).
        directions: #K×3 directions in space, projected to the tangent plane at each vertex.
        mollify: relative mollification margin.
        return_info: also return a dict (path, ``singular_faces``, ``total_index`` — n·χ on a
            closed surface —, ``face_singularity`` — #F int array: the index of each face of
            F, in units of 1/n, from the field at its corners and the transport along its
            edges; sums to n·χ on a closed mesh; what ``ifem field -o OUT.ply`` writes as the
            face property ``singularity``; empty for point clouds —, ``constrained``,
            ``energy``, ``orientation_conflicts`` — neighbour pairs whose oriented normals
            still disagree on the frame path —, ``components`` (connected components: a
            triangle soup's pieces), ``free_components`` (those that took their own smoothest
            field), ``empty_components`` (those without a field: vectors 0 there),
            ``flat_components`` (the empty ones without area in space, e.g. a lone zero-area
            face) and ``skipped_constraints`` (directions given on them), ...; with curves, ``curves``: what inserting
            them did, as :func:`curve_poisson`'s info).
        normals: optional #V×3 normals of a point cloud (rows zero or not finite: PCA).
        path: ``'auto'``, ``'manifold'``, ``'tufted'`` or ``'pointcloud'``.
        knn: neighbours per point on the point-cloud path.
        curves: None, or curves to align the field to: a list of :class:`Curve` (or dicts of
            its arguments), one Curve, or a curves file's path (as :func:`curve_poisson`; the
            curves' values are not used and may be omitted, e.g. ``ifem.Curve([3, 8, 20, 31],
            bezier=True)``). Needs an edge-manifold, orientable mesh (path 'auto' or
            'manifold').
        max_iterations, accept_partial: with curves, FlipOut's cap on them and whether curves
            left at it are accepted (as :func:`curve_poisson`; ``--max-iterations``,
            ``--accept-partial``).

    Returns:
        ``vectors`` (#V×3: a unit tangent vector per vertex, one of the n directions; 0 where
        the field has no direction), ``angle`` (#V: that direction's angle in the vertex's own
        coordinate, 0 along its first edge, counter-clockwise with the faces' orientation; on
        the frame path from the x axis projected to the tangent plane), ``singularity`` (#V:
        indices in units of 1/n of the singular faces, each counted on one of its corners; the
        input's faces on the frame path, none for point clouds), and ``info`` when asked.

    Raises:
        InvalidInput: bad arrays, symmetry < 1, a constraint vertex out of range or a direction
            normal to the surface, ``align_boundary`` on a point cloud, curves on a point
            cloud or a mesh that is not edge-manifold and orientable, a bad curve (named
            ``curves[i]`` or ``file:line``), two curves sharing an edge.
        IoError: an unreadable curves file.

    Example:
        >>> vectors, angle, singularity = ifem.direction_field(
        ...     V, F, symmetry=4, curves=[ifem.Curve([0, 40, 77]), ifem.Curve([5, 9, 13],
        ...                                                            closed=True)])
    """
    if curves is None and (max_iterations is not None or accept_partial):
        raise InvalidInput("max_iterations and accept_partial apply to curves (FlipOut on the "
                           "curves), which were not given")
    V, F, normals = _input(V, F, normals)
    specs = None if curves is None else _specs(curves)
    vectors, angle, singularity, info = _ifem.direction_field(
        V, None if F is None or np.size(F) == 0 else F, int(symmetry), bool(align_boundary),
        constraint_vertices, directions, normals, float(mollify), str(path), int(knn), specs,
        _flipout_cap(max_iterations), bool(accept_partial))
    out = (np.ascontiguousarray(vectors), angle, singularity)
    return out + (info,) if return_info else out


#: Deprecated: the old name of :func:`field`.
direction_field = field


class VectorHeatSolver:
    """The Vector Heat Method (Sharp, Soliman, Crane 2019) on a mesh or point cloud: factors
    once, then parallel transport and logarithmic maps cost a few back-substitutions each. Same
    as ``ifem transport`` / ``ifem logmap``; like potpourri3d's ``MeshVectorHeatSolver`` and
    ``PointCloudHeatSolver``, with 3D vectors in and out.

    Args:
        V: #V×3 positions, or a file's path (read with its normals, as the CLI reads it).
        F: #F×3 vertex ids; ``None`` (or empty) for a point cloud. Nonmanifold and
            non-orientable meshes (the tufted path) and point clouds use per-vertex 3D frames
            from the normals, oriented by propagation (see :func:`direction_field`); the log
            map's angle 0 is then the x axis projected to the source's tangent plane.
        mollify: relative mollification margin.
        normals: optional #V×3 normals of a point cloud (a file's own when V is a path).
        path: ``'auto'``, ``'manifold'``, ``'tufted'`` or ``'pointcloud'``.
        knn: neighbours per point on the point-cloud path.
    """

    def __init__(self, V, F=None, mollify=1e-5, *, normals=None, path="auto", knn=30):
        V, F, normals = _input(V, F, normals)
        self._solver = _ifem.VectorHeat(V, None if F is None or np.size(F) == 0 else F, normals,
                                        float(mollify), str(path), int(knn))

    def transport(self, source, vector):
        """Parallel transport of a 3D vector at vertex ``source`` (projected to its tangent
        plane, length kept) to every vertex along shortest geodesics: #V×3 tangent vectors, finite
        wherever the source reaches, NaN elsewhere (other components, e.g. a triangle soup's
        other pieces; as ``distance`` gives inf there)."""
        return self._solver.transport(int(source), np.asarray(vector, float).reshape(1, 3))

    def logmap(self, source, method="blend", return_distance=False):
        """The logarithmic map about vertex ``source``: #V×2 Riemannian coordinates
        (u, v) = d·(cos θ, sin θ), d the geodesic distance, θ the direction at the source
        counter-clockwise from its first edge's direction (``log_map`` is its deprecated old
        name). Vertices no path reaches (another component, unreferenced) are (nan, nan), their
        distance ``inf``; vertices where the heat underflows are nan with distance nan.

        Args:
            method: ``'blend'`` (the default: per vertex the affine value where the two
                methods agree, the vector heat value where they do not), ``'vector-heat'``
                (the heat-method distance as radius) or ``'affine'`` (the affine heat method:
                exact on flat regions, much smaller errors near the source and in angle, its
                radius short far away on curved surfaces), as ``ifem logmap --method``.
            return_distance: also return d (#V, ``inf`` where unreached).

        Returns:
            uv, or (uv, distance) with return_distance.
        """
        uv, d, _ = self._solver.log_map(int(source), str(method))
        return (uv, d) if return_distance else uv

    #: Deprecated: the old name of :meth:`logmap`.
    log_map = logmap

    @property
    def info(self):
        """What preparing the surface chose and did (path, flips, ...)."""
        return self._solver.info()


def _required(x, name, command):
    if x is None:
        raise InvalidInput(f"{name} is required (the CLI's --{name} of `ifem {command}`)")
    return x


def transport(V, F=None, source=None, vector=None, *, mollify=1e-5, normals=None, path="auto",
              knn=30):
    """Parallel transport of a tangent vector from one vertex to every vertex, as ``ifem
    transport MESH --source S --vector X,Y,Z`` (the Vector Heat Method; for many queries on one
    surface build a :class:`VectorHeatSolver`).

    Args:
        V: #V×3 positions, or a file's path (read with its normals, as the CLI reads it).
        F: #F×3 vertex ids; ``None`` for a point cloud (and when V is a path).
        source: the source vertex id.
        vector: the 3D vector at the source (projected to its tangent plane, length kept).
        mollify, normals, path, knn: as :class:`VectorHeatSolver`.

    Returns:
        #V×3 tangent vectors: finite at every vertex the source reaches, NaN (all three
        coordinates) at the others, as the CLI writes them.
    """
    _required(source, "source", "transport")
    _required(vector, "vector", "transport")
    solver = VectorHeatSolver(V, F, mollify, normals=normals, path=path, knn=knn)
    return solver.transport(source, vector)


def logmap(V, F=None, source=None, *, method="blend", return_distance=False, mollify=1e-5,
           normals=None, path="auto", knn=30):
    """The logarithmic map about one vertex, as ``ifem logmap MESH --source S`` (the Vector Heat
    Method; for many sources on one surface build a :class:`VectorHeatSolver`).

    Args:
        V: #V×3 positions, or a file's path (read with its normals, as the CLI reads it: the
            same file gives the same map in both).
        F: #F×3 vertex ids; ``None`` for a point cloud (and when V is a path).
        source: the source vertex id.
        method, return_distance: as :meth:`VectorHeatSolver.logmap`.
        mollify, normals, path, knn: as :class:`VectorHeatSolver`.

    Returns:
        #V×2 Riemannian coordinates (u, v) = d·(cos θ, sin θ), (nan, nan) where unreached (see
        :meth:`VectorHeatSolver.logmap`); with return_distance also d (``inf`` where
        unreached).
    """
    _required(source, "source", "logmap")
    solver = VectorHeatSolver(V, F, mollify, normals=normals, path=path, knn=knn)
    return solver.logmap(source, method=method, return_distance=return_distance)


__all__ = ["field", "direction_field", "transport", "logmap", "VectorHeatSolver"]
