"""Moved to ``geompm.contract.registry``: this path keeps working for plugins written before, with a DeprecationWarning."""

from geompm._moved import forward

__getattr__ = forward("geompm.registry", "geompm.contract.registry")
