"""(filled in by the solvers bindings)."""

__all__ = []
