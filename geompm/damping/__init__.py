"""Damping stages (geompm.damping entry-point group)."""
