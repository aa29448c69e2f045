"""ifem: intrinsic finite elements on bad meshes and point clouds, from Python.

Arrays in, numpy arrays and scipy.sparse matrices out; results are always on the input's own
vertices, in the input's order. ``V`` is a #V×3 array of positions (any real dtype; float64
C-order is used without conversion), ``F`` a #F×3 array of vertex ids (any integer dtype).

Conventions shared by every function:

- ``L`` is the cotan Laplacian as a positive semi-definite matrix (positive diagonal,
  ``L @ 1 == 0``), the finite-element stiffness matrix; libigl's ``cotmatrix`` is ``-L``.
  ``M`` is the lumped (diagonal) mass matrix. Both are ``scipy.sparse.csc_matrix``.
- Bad input raises :class:`ifem.InvalidInput` (a ``ValueError``) with a message naming the
  argument, the row or the index; files that cannot be read raise :class:`ifem.IoError` (an
  ``OSError``); numerical failures :class:`ifem.SolverError` (a ``RuntimeError``).
- Long computations release the GIL.

One name per operation: the functions named after the CLI's commands (``ifem.info``,
``ifem.laplacian``, ``ifem.refine``, ``ifem.distance``, ``ifem.eigen``, ``ifem.poisson``,
``ifem.geodesic``, ``ifem.field``, ``ifem.transport``, ``ifem.logmap``, ``ifem.view``,
``ifem.render``, ``ifem.isolines``, ``ifem.trace``, ``ifem.simplify``) also take a file's path instead of ``V, F``,
read with its normals as the CLI reads it; ``knn`` is the neighbour count of the point-cloud path everywhere. Older names (``heat_distance``, ``direction_field``,
``mesh_info``, ``VectorHeatSolver.log_map``) are deprecated aliases of the same functions.

See the README's "Python" section for a quick start, the name table (operation | CLI | Python |
C++) and a table mapping robust-laplacian's and potpourri3d's calls to ifem's.
"""

from ._errors import *  # noqa: F401,F403
from ._errors import __all__ as _errors_all
from ._mesh import *  # noqa: F401,F403
from ._mesh import __all__ as _mesh_all
from ._operators import *  # noqa: F401,F403
from ._operators import __all__ as _operators_all
from ._solvers import *  # noqa: F401,F403
from ._solvers import __all__ as _solvers_all
from ._refine import *  # noqa: F401,F403
from ._refine import __all__ as _refine_all
from ._geodesic import *  # noqa: F401,F403
from ._geodesic import __all__ as _geodesic_all
from ._curves import *  # noqa: F401,F403
from ._curves import __all__ as _curves_all
from ._fields import *  # noqa: F401,F403
from ._fields import __all__ as _fields_all
from ._view import *  # noqa: F401,F403
from ._view import __all__ as _view_all
from ._render import *  # noqa: F401,F403
from ._render import __all__ as _render_all
from ._isolines import *  # noqa: F401,F403
from ._isolines import __all__ as _isolines_all
from ._signed import *  # noqa: F401,F403
from ._signed import __all__ as _signed_all
from ._trace import *  # noqa: F401,F403
from ._trace import __all__ as _trace_all
from ._exact import *  # noqa: F401,F403
from ._exact import __all__ as _exact_all
from ._simplify import *  # noqa: F401,F403
from ._simplify import __all__ as _simplify_all

__version__ = "0.1.0"

__all__ = (_errors_all + _mesh_all + _operators_all + _solvers_all + _refine_all +
           _geodesic_all + _curves_all + _fields_all + _view_all + _render_all + _isolines_all +
           _signed_all + _trace_all + _exact_all + _simplify_all)
