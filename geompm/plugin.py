"""Moved to ``geompm.contract.plugin``: this path keeps working for plugins written before, with a DeprecationWarning."""

from geompm._moved import forward

__getattr__ = forward("geompm.plugin", "geompm.contract.plugin")
