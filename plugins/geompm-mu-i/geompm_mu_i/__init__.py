"""mu(I) granular rheology plugin for geompm."""

from .law import MuI

__all__ = ["MuI"]
