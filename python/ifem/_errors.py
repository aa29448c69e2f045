"""ifem's exceptions, one per C++ exception class, with the same messages.

Every exception ifem raises derives from :class:`ifem.Error`; each also derives from the
built-in exception a Python user would catch for it:

============================  =================  ======================================
ifem (C++)                    Python             raised for
============================  =================  ======================================
``ifem::InvalidInput``        ``ValueError``     bad arrays, indices out of range, bad options
``ifem::NonManifoldInput``    ``ValueError``     a mesh the manifold path cannot represent
``ifem::NonOrientableInput``  ``ValueError``     a non-orientable gluing (manifold path)
``ifem::IoError``             ``OSError``        unreadable / malformed / unwritable files
``ifem::SolverError``         ``RuntimeError``   factorization or eigensolver failures
``ifem::TraceError``          ``RuntimeError``   a straight-line trace that could not finish
============================  =================  ======================================
"""


class Error(Exception):
    """Base of every exception ifem raises."""


class InvalidInput(Error, ValueError):
    """Input that cannot be used as given (shape, dtype, NaN, index out of range, option)."""


class NonManifoldInput(InvalidInput):
    """An edge with 3+ faces or a non-orientable gluing where a manifold mesh is needed."""


class NonOrientableInput(NonManifoldInput):
    """A gluing with no consistent orientation where an orientable mesh is needed."""


class IoError(Error, OSError):
    """A file that cannot be read or written (missing, unknown format, malformed)."""


class SolverError(Error, RuntimeError):
    """A numerical failure: a matrix not positive definite, an eigensolver not converging."""


class TraceError(Error, RuntimeError):
    """A straight-line trace over the surface that could not finish."""


__all__ = ["Error", "InvalidInput", "NonManifoldInput", "NonOrientableInput", "IoError",
           "SolverError", "TraceError"]
