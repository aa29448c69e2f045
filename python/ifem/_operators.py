"""The intrinsic Delaunay cotan Laplacian and mass matrix of meshes and point clouds."""

import numpy as np
import scipy.sparse

from . import _ifem
from ._errors import InvalidInput
from ._inputs import surface as _input


def _csc(parts):
    data, indices, indptr, shape = parts
    return scipy.sparse.csc_matrix((data, indices, indptr), shape=shape, copy=False)


def _diag(m):
    # built from its three arrays: scipy.sparse.diags(m, format="csc") costs a few percent of a
    # whole laplacian() call at 1M faces
    n = len(m)
    ids = np.arange(n, dtype=np.int32)
    return scipy.sparse.csc_matrix((m, ids, np.arange(n + 1, dtype=np.int32)), shape=(n, n),
                                   copy=False)


def laplacian(V, F=None, mollify=1e-5, path="auto", intrinsic_delaunay=True, return_info=False,
              *, knn=30, normals=None):
    """The cotan Laplacian ``L`` and lumped mass ``M`` of a triangle mesh, on its vertices.

    Built on the intrinsic Delaunay triangulation of the mesh: same vertices, same geometry,
    edges flipped until every cotan weight is non-negative (the maximum principle holds, and
    slivers no longer break solvers). Nonmanifold and non-orientable meshes go through the
    tufted cover (Sharp & Crane 2020), so every mesh gets a Laplacian.

    Sign convention: ``L`` is symmetric positive semi-definite, ``L @ 1 == 0``, off-diagonals
    ≤ 0 on the intrinsic Delaunay triangulation; libigl's ``cotmatrix`` is ``-L``, and
    robust-laplacian's ``mesh_laplacian`` returns the same ``L`` as here. Solve ``L u = M f``
    for Poisson problems.

    Args:
        V: #V×3 positions, or a file's path (read with its normals, as ``ifem laplacian``).
        F: #F×3 vertex ids; None (or a file without faces): a point cloud, as
            :func:`point_cloud_laplacian` with ``knn`` and ``normals``.
        mollify: relative mollification margin (every triangle made to satisfy
            a + b − c ≥ mollify × mean edge length by adding one length δ to every edge).
        path: ``'auto'`` (manifold when possible, else the tufted cover), ``'manifold'`` (raise
            NonManifoldInput when the mesh cannot take it) or ``'tufted'``.
        intrinsic_delaunay: flip to the intrinsic Delaunay triangulation (default); False gives
            the plain cotan Laplacian of the input triangles.
        return_info: also return a dict: ``path``, ``reason``, ``flips``, ``mollify_delta``,
            ``dropped_faces``, ``reoriented_faces``, ``unreferenced_vertices``, ``seconds`` (the
            C++ library's own time; the rest of the call is the binding's).
        knn, normals: a point cloud's neighbours per point and optional #V×3 normals.

    Returns:
        ``L, M`` (scipy.sparse.csc_matrix, #V×#V; unreferenced vertices have zero rows and zero
        mass), and ``info`` when asked.
    """
    V, F, normals = _input(V, F, normals)
    if F is None:
        return point_cloud_laplacian(V, knn, normals, mollify, return_info)
    parts, m, info = _ifem.laplacian(V, F, float(mollify), str(path), bool(intrinsic_delaunay))
    L, M = _csc(parts), _diag(m)
    return (L, M, info) if return_info else (L, M)


def point_cloud_laplacian(P, knn=30, normals=None, mollify=1e-5, return_info=False, *, k=None):
    """The Laplacian ``L`` and mass ``M`` of a point cloud (Sharp & Crane 2020).

    Each point's k nearest neighbours are projected to its tangent plane and Delaunay
    triangulated there; the local triangles are glued into a tufted cover, mollified and
    flipped to intrinsic Delaunay. Same sign convention as :func:`laplacian`.

    Args:
        P: #P×3 points.
        knn: neighbours per point, in [2, #P) (``k=`` is its deprecated old name).
        normals: optional #P×3 normals for the tangent planes (rows that are zero or not
            finite fall back to PCA of the neighbourhood).
        mollify: relative mollification margin.
        return_info: also return a dict about the construction.

    Returns:
        ``L, M`` (scipy.sparse.csc_matrix, #P×#P), and ``info`` when asked.
    """
    if k is not None:
        if knn != 30 and knn != k:
            raise InvalidInput(f"give knn (k is its deprecated old name), not both: knn={knn!r}, "
                               f"k={k!r}")
        knn = k
    parts, m, info = _ifem.point_cloud_laplacian(P, int(knn), normals, float(mollify))
    L, M = _csc(parts), _diag(m)
    return (L, M, info) if return_info else (L, M)


__all__ = ["laplacian", "point_cloud_laplacian"]
