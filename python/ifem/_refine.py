"""(filled in by the refine bindings)."""

__all__ = []
