"""Rigid wall on a face of the grid (``side`` x-, x+, y-, y+, z-, z+).

Acts on the nodes on and beyond the face (global index <= 0 for a '-' side,
>= ncells for a '+' side), with the unit normal pointing into the domain, by
the rule of contact.py: ``fixed`` (no slip), ``slip`` (free to separate) or
``friction`` (Coulomb, coefficient ``friction``).  After G2P a particle that
ended beyond the face is put back on it (halfspace_guard.py).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numba import njit
from pydantic import Field

from ..plugin import Params
from ..stages import GridStage, ParticleStage
from .contact import CONDITIONS, apply_condition
from .halfspace_guard import halfspace_guard

SIDES = ("x-", "x+", "y-", "y+", "z-", "z+")


class WallParams(Params):
    side: Literal["x-", "x+", "y-", "y+", "z-", "z+"] = Field(description="Face of the grid")
    condition: Literal["slip", "fixed", "friction"] = Field("slip", description="Contact condition")
    friction: float = Field(0.0, ge=0.0, description="Coulomb coefficient mu [-] (condition 'friction')")


@njit(cache=True)
def wall_apply(g_vel, g_mass, lo, nloc, axis, normal, first, last, condition, mu):
    """Apply the wall to window nodes whose index along ``axis`` is in [first, last]."""
    nn, d = g_vel.shape
    i0 = max(first - lo[axis], 0)
    i1 = min(last - lo[axis], nloc[axis] - 1)
    if i1 < i0:
        return
    inner = 1
    for a in range(axis + 1, d):
        inner *= nloc[a]
    outer = nn // (inner * nloc[axis])
    for o in range(outer):
        for i in range(i0, i1 + 1):
            for q in range(inner):
                idx = (o * nloc[axis] + i) * inner + q
                if g_mass[idx] > 0.0:
                    apply_condition(g_vel, idx, normal, condition, mu)


class Wall(GridStage, ParticleStage):
    name = "wall"
    description = "Rigid wall on a grid face: slip, fixed (no-slip) or Coulomb friction"
    Params = WallParams

    @classmethod
    def check(cls, params, case):
        if SIDES.index(params.side) // 2 >= case.dimension:
            return [("side", f"'{params.side}' does not exist in a {case.dimension}D case")]
        return []

    def setup(self, scene):
        self.axis = SIDES.index(self.params.side) // 2
        minus = self.params.side.endswith("-")
        n = int(scene.grid.ncells[self.axis])
        self.normal = np.zeros(scene.dim)
        self.normal[self.axis] = 1.0 if minus else -1.0
        self.first, self.last = (-(1 << 40), 0) if minus else (n, 1 << 40)
        self.condition = CONDITIONS[self.params.condition]
        self.point = scene.grid.origin.astype(float).copy()
        if not minus:
            self.point[self.axis] = scene.grid.upper[self.axis]

    def apply_grid(self, view, dt, time, remap):
        wall_apply(view.g_vel, view.g_mass, view.lo, view.nloc, self.axis, self.normal,
                   self.first, self.last, self.condition, self.params.friction)

    def apply_particles(self, state, dt, time):
        halfspace_guard(state.p_x, state.p_v, self.point, self.normal, self.condition, self.params.friction)
