"""geompm's version: the lowest module of the package, so that any layer may say which geompm wrote a file."""

__version__ = "0.1.0"
