"""Moved to ``geompm.contract.layout``: this path keeps working for plugins written before, with a DeprecationWarning."""

from geompm._moved import forward

__getattr__ = forward("geompm.layout", "geompm.contract.layout")
