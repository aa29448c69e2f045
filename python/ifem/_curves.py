"""(filled in by the curves bindings)."""

__all__ = []
