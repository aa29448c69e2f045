"""Intrinsic simplification: a coarse intrinsic triangulation over a subset of the input's
vertices, and the prolongation P from it to the input."""

import scipy.sparse

from . import _ifem
from ._inputs import surface as _input


def simplify(V, F=None, vertices=None, ratio=None, mollify=1e-5, path="auto",
             return_info=False, progress=None, tangent=False):
    """Coarsens a mesh by intrinsic vertex removal (as ``ifem simplify``).

    The cheapest vertex (star area × (|angle defect| + 4π / area)) is flipped to degree 3 (an
    ear on the boundary) and removed, then the new sides are flipped back to intrinsic Delaunay;
    removed vertices are tracked as points of coarse triangles. Kept exactly: each component's
    Euler characteristic, boundary loops and total area (one uniform rescale per component).
    A vertex that cannot be flipped to degree 3 is removed by flattening (its neighbours'
    polygon laid out convex; ``info['flattened']``). Nonmanifold meshes and point clouds go
    through the tufted cover, whose pillows (isolated triangles zipped to their back) are
    deleted (``info['pillows']``); a point cloud's cover is built without self-edges (its
    Delaunay flips skip those), so point clouds reach a ratio of 0.1; vertices that still cannot
    be removed (a link no triangulation without a self-edge replaces) are kept and counted in
    ``info['stuck']``.

    Args:
        V: #V×3 positions, or a file's path.
        F: #F×3 vertex ids (None with a path).
        vertices: stop at this many vertices (in [1, #V)); or
        ratio: keep this fraction of the vertices, in (0, 1]. Give exactly one.
        mollify: relative mollification margin of the input (as :func:`laplacian`).
        path: ``'auto'``, ``'manifold'`` or ``'tufted'``.
        return_info: also return a dict (path, counts, ``side_lengths``: #Fc×3 intrinsic
            lengths of the coarse faces, side s from corner s to s+1; ``multiplicity``: 2 on the
            tufted cover).
        progress: None or a callable ``progress(fraction, stage)``, stage ``"simplify"``.
        tangent: also return the tangent-vector prolongation ``P_tangent`` (after ``P``):
            scipy.sparse.csc_matrix, complex, #V×#Vc; a coarse tangent field (one complex number
            per coarse vertex in the coarse triangulation's angular coordinates: the
            vertex's reference edge at angle 0, angles scaled to 2π) to the input's
            coordinates. Entries are P's times unit complex numbers (the transport from the coarse
            vertex through its coarse face to the input vertex), so ``abs(P_tangent) == P``
            where no coarse face repeats a corner; ``P_tangent.conj().T`` restricts.

    Returns:
        ``faces`` (#Fc×3, ids of the coarse vertices 0..#Vc−1), ``kept`` (#Vc input vertex ids:
        coarse vertex c is input vertex ``kept[c]``) and ``P`` (scipy.sparse.csc_matrix,
        #V×#Vc: rows ≥ 0 summing to 1, ``P[kept[c], c] == 1``; ``P @ u`` interpolates a coarse
        piecewise-linear function, ``P.T`` restricts, ``P.T @ L @ P`` is the Galerkin coarse
        operator); then ``P_tangent`` when ``tangent``, and ``info`` when asked.

    Raises:
        InvalidInput: neither or both of vertices / ratio, or one out of range.
    """
    V, F, _ = _input(V, F)
    n = 0 if vertices is None else int(vertices)
    r = 0.0 if ratio is None else float(ratio)
    faces, kept, parts, lengths, info, tparts = _ifem.simplify(
        V, F, n, r, float(mollify), str(path), progress, bool(tangent))
    data, indices, indptr, shape = parts
    P = scipy.sparse.csc_matrix((data, indices, indptr), shape=shape, copy=False)
    info["side_lengths"] = lengths
    out = (faces, kept, P)
    if tangent:
        data, indices, indptr, shape = tparts
        out += (scipy.sparse.csc_matrix((data, indices, indptr), shape=shape, copy=False),)
    return out + (info,) if return_info else out


__all__ = ["simplify"]
