"""Boundary conditions on grid velocities (geompm.boundaries entry-point group)."""
