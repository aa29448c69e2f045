"""Headless pictures: a mesh, one per-vertex field and curves as an RGB array or a PNG file."""

import math
import os

import numpy as np

from . import _ifem
from ._errors import InvalidInput
from ._inputs import is_path


def render(V, F=None, field=None, output=None, *, view="front", azimuth=None, elevation=None,
           size=(800, 600), colormap="viridis", range=None, isolines=0, wireframe=False,
           curves=None, curve_width=3.0, triangulation=None, legend=False, supersample=2,
           fill=0.9, return_range=False):
    """A picture of a mesh coloured by a per-vertex field, without a display (``ifem render``).

    A software rasterizer (no GPU, display or browser): the same call gives the same pixels.
    The camera is orthographic and aimed at the centre of the bounding box; the whole scene
    fits the picture (its bounding sphere spans ``fill`` × min(width, height) / 2 pixels).
    The colour is the field through the colour map, shaded by a light from the camera.

    Args:
        V: #V×3 positions, or a file's path (any format ifem reads; its faces are used).
        F: #F×3 vertex ids; None (or a file without faces): the vertices are drawn as points.
        field: #V values (non-finite ones drawn grey); with a path, also the name of one of its
            PLY vertex properties; None: the file's first property, or a grey surface.
        output: a ``.png`` path to write (None: only return the array).
        view: ``'front'`` (camera on +z, +y up), ``'back'``, ``'left'``, ``'right'`` (on +x),
            ``'top'`` (on +y, −z up) or ``'bottom'``.
        azimuth, elevation: degrees, override the view's (direction
            (cos e sin a, sin e, cos e cos a) from the centre to the camera).
        size: (width, height) in pixels.
        colormap: ``'viridis'`` (dark violet low → yellow high), ``'diverging'`` (blue → grey →
            red; range symmetric about 0 by default) or ``'gray'``.
        range: (lo, hi) of the colour map; None: the field's finite min and max.
        isolines: N dark isolines at lo + k (hi − lo) / (N + 1), k = 1..N (needs a field).
        wireframe: draw the mesh's edges.
        curves: polylines to draw in red: a list of k×3 arrays, or a file's path: an OBJ's
            'l' lines (``--curves-out``, ``ifem geodesic -o``) or a PLY line set (``ifem refine
            --lines``: the intrinsic edges traced over the input).
        curve_width: the curves' width in pixels.
        triangulation: a :class:`RefinedTriangulation` made on this mesh (:func:`refine`,
            :func:`load_refined`): its intrinsic edges traced over the input, drawn in blue
            (as ``ifem render --triangulation`` and :func:`view` draw them).
        legend: a colour bar at the right edge with the range's ends written beside it (and a
            tick per isoline); the mesh is framed left of it. Needs a field.
        supersample: anti-aliasing factor S in 1..4 (drawn S× larger, then averaged).
        fill: the bounding sphere's share of half the picture (> 1 zooms in).
        return_range: also return the colour range used, (lo, hi) (NaN without a field).

    Returns:
        The picture, a height×width×3 uint8 array (rows top to bottom), and ``(lo, hi)`` when
        asked.

    Raises:
        InvalidInput: bad arrays, an unknown view, colour map or property, a size or option out
            of range, isolines without a field, a triangulation made on another mesh.
        IoError: a file that cannot be read or written.
    """
    if is_path(V) and F is None:
        V, F, info = _ifem.read_mesh(os.fsdecode(V))
        properties = info["vertex_properties"]
        if field is None and properties:
            field = next(iter(properties.values()))
        elif isinstance(field, str):
            if field not in properties:
                raise InvalidInput(f"render: no per-vertex property '{field}' (the input has: "
                                   f"{', '.join(properties) or 'none'})")
            field = properties[field]
        if np.size(F) == 0:
            F = None
    if isinstance(field, str):
        raise InvalidInput("render: a property name needs V to be a file's path")
    if is_path(curves):
        curves = [np.asarray(c) for c in _ifem.read_polylines(os.fsdecode(curves))]
    az, el = _ifem.named_view(view)
    if azimuth is not None:
        az = float(azimuth)
    if elevation is not None:
        el = float(elevation)
    lo, hi = (math.nan, math.nan) if range is None else (float(range[0]), float(range[1]))
    width, height = size
    out = "" if output is None else os.fsdecode(output)
    image, lo, hi = _ifem.render(V, F, field, curves, (int(width), int(height)), az, el,
                                 colormap, (lo, hi), int(isolines), bool(wireframe),
                                 int(supersample), float(fill), float(curve_width),
                                 bool(legend),
                                 None if triangulation is None else triangulation._h, out)
    return (image, (lo, hi)) if return_range else image


__all__ = ["render"]
