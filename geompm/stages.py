"""Moved to ``geompm.contract.stages``: this path keeps working for plugins written before, with a DeprecationWarning."""

from geompm._moved import forward

__getattr__ = forward("geompm.stages", "geompm.contract.stages")
