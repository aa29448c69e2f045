"""(filled in by the geodesic bindings)."""

__all__ = []
