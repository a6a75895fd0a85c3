"""Rigid obstacles (geompm.obstacles entry-point group)."""
