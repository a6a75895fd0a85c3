"""Particle-level guard of a rigid half-space (plane, grid wall): no particle ends a step behind it.

Grid contact acts on the nodes on or behind the surface; a particle can
still end a step behind it (a fast particle, or a plane that cuts the cells
between nodes).  After G2P every particle with signed distance
phi = (x - point) . n < 0 is put back on the surface, x <- x - phi n, and its
velocity gets the same rule as the nodes (boundaries/contact.py: slip, fixed
or Coulomb friction).  phi is exact for a plane, so the guard leaves
phi >= 0 up to round-off.  A half-space cannot be crossed within a step
without ending behind it, so the end position is the whole test.
"""

from __future__ import annotations

from numba import njit

from .contact import apply_condition


@njit(cache=True)  # serial: one dot product per particle
def halfspace_guard(p_x, p_v, point, normal, condition, mu):
    """Put back the particles behind the plane through ``point`` with unit ``normal``; returns how many."""
    n, d = p_x.shape
    count = 0
    for p in range(n):
        phi = 0.0
        for a in range(d):
            phi += (p_x[p, a] - point[a]) * normal[a]
        if phi < 0.0:
            for a in range(d):
                p_x[p, a] -= phi * normal[a]
            apply_condition(p_v, p, normal, condition, mu)
            count += 1
    return count
