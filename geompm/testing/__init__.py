"""Reusable test suites for plugins (import them from a third-party package's tests)."""

from geompm.testing.conformance import MATERIAL_CHECKS, check_material, update_stress

__all__ = ["MATERIAL_CHECKS", "check_material", "update_stress"]
