"""The input of every operation, as the CLI takes it: a file's path, or arrays.

``ifem COMMAND MESH`` reads MESH with its normals (an ``.xyz`` file's ``nx ny nz`` columns, a
PLY's ``nx ny nz`` properties, an OBJ's ``vn`` lines); a point cloud's normals then set its
tangent planes. The Python functions named after the CLI's commands (``ifem.distance``,
``ifem.logmap``, ...) do the same: ``V`` may be a path, read with the file's normals unless
``normals=`` is given, so ``ifem.logmap("cloud.xyz", source=0)`` and ``ifem logmap cloud.xyz
--source 0`` compute the same. With arrays, give the normals with ``normals=`` (None: PCA of
the neighbours, as for a file without normals).
"""

import os

import numpy as np

from . import _ifem


def is_path(x):
    return isinstance(x, (str, bytes, os.PathLike))


def surface(V, F=None, normals=None):
    """(V, F, normals): a path (with F None) read with its faces (None for a point cloud) and its
    normals (unless ``normals`` is given); anything else as given (a string V with an F is
    refused by the binding as a V that is not an array)."""
    if is_path(V) and F is None:
        V, F, info = _ifem.read_mesh(os.fsdecode(V))
        if normals is None:
            normals = info.get("normals")
        if np.size(F) == 0:
            F = None
    return V, F, normals


__all__ = []
