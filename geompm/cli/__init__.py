"""The ``geompm`` command (``main.py``: run, validate, info, plot, plugins, schema; ``study``, ``calibrate`` and
``bench`` come from their packages; ``cuda_check.py``: ``geompm cuda-check``)."""

from geompm.cli.main import build_parser, main

__all__ = ["build_parser", "main"]
