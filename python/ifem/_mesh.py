"""Reading meshes and point clouds, writing PLY files with per-vertex properties."""

import os

from . import _ifem
from ._inputs import surface as _input


def read_mesh(path, return_info=False, progress=None):
    """Reads a mesh or a point cloud: OBJ, OFF, PLY (ASCII / binary), STL (ASCII / binary), XYZ.

    Polygons are triangulated (each n-gon into n − 2 triangles); a file without faces is a
    point cloud and gives ``F`` of shape (0, 3).

    Args:
        path: the file (str or os.PathLike); the format comes from the extension.
        return_info: also return a dict with what the file held besides V and F: ``format``,
            ``polygons``, ``non_triangles``, ``welded_vertices`` (STL), ``normals`` (#V×3 when
            the file has them) and ``vertex_properties`` (name → #V array, PLY).
        progress: None (default: nothing is reported, nothing printed) or a callable
            ``progress(fraction, stage)``, stage ``"read"``: the bytes read over the file's size
            (0 first, non-decreasing, exactly 1 last).

    Returns:
        ``V`` (#V×3 float64, file order) and ``F`` (#F×3 int32), and ``info`` when asked.

    A point cloud's normals are not in ``V``: to compute as ``ifem COMMAND FILE`` does, pass the
    path itself (``ifem.logmap("cloud.ply", source=0)``) or ``normals=info["normals"]``; arrays
    alone take PCA normals, whose orientation may differ (a mirrored log map).

    Raises:
        IoError: missing file, unknown extension, malformed content, a face index out of range
            or a non-finite coordinate, with the file and line (or byte offset).
    """
    V, F, info = _ifem.read_mesh(os.fspath(path), progress)
    return (V, F, info) if return_info else (V, F)


def write_ply(path, V, F=None, binary=True, **vertex_properties):
    """Writes a PLY mesh (or point cloud when ``F`` is None) with per-vertex properties.

    The file opens in MeshLab, ParaView and Polyscope; each keyword argument becomes a
    ``double`` vertex property of that name, e.g. ``write_ply("d.ply", V, F, distance=d)``.

    Args:
        path: the file to write (atomically: a temporary file, then renamed).
        V: #V×3 positions.
        F: #F×3 vertex ids, or None for a point cloud.
        binary: binary little-endian PLY (default) or ASCII.
        **vertex_properties: name=array, each with one value per vertex.

    Raises:
        InvalidInput: bad shapes or a property of the wrong length.
        IoError: the file cannot be written.
    """
    _ifem.write_ply(os.fspath(path), V, F, dict(vertex_properties), bool(binary))


def info(V, F=None, knn=30, mollify=1e-5, path="auto", *, normals=None):
    """What a mesh (or point cloud) is made of and what ifem does with it: ``ifem info --json``
    (``mesh_info`` is its deprecated old name).

    For a mesh: counts (``vertices``, ``edges``, ``faces``, ``polygons``,
    ``unreferenced_vertices``), topology (``components``, ``boundary_edges``, ``boundary_loops``,
    ``euler_characteristic``, ``genus`` — None unless the surface is orientable and manifold),
    defects (``nonmanifold_edges``, ``nonmanifold_vertices``, ``dropped_degenerate_faces``,
    ``duplicate_faces``, ``reoriented_faces``), the input's corner angles (``min_angle_deg``,
    ``max_angle_deg``) and ``non_delaunay_share``, ``flips_to_idt``, ``mollify_delta``, and the
    ``path`` ifem takes (manifold / tufted / pointcloud) with ``path_reason``.
    For a point cloud (F None or empty): ``points``, ``k``, ``local_triangles``,
    ``isolated_points``, ``starless_points``, ``coincident_points``, cover sizes, ``area``.

    Args:
        V: #V×3 positions, or a file's path (read with its normals, as the CLI reads it).
        F: #F×3 vertex ids, or None for a point cloud.
        knn: neighbours per point on the point-cloud path (as the solvers' knn).
        normals: optional #V×3 normals of a point cloud (a file's own when V is a path).
        mollify: relative mollification margin.
        path: 'auto', 'manifold', 'tufted' or 'pointcloud' (a mesh's vertices as a cloud).

    Returns:
        dict, with the same keys and values as ``ifem info MESH --json``.
    """
    V, F, normals = _input(V, F, normals)
    return _ifem.mesh_info(V, F, int(knn), float(mollify), str(path), normals)


#: Deprecated: the old name of :func:`info`.
mesh_info = info

__all__ = ["read_mesh", "write_ply", "info", "mesh_info"]
