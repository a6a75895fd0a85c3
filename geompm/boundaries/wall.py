"""Rigid wall on a face of the grid (``side`` x-, x+, y-, y+, z-, z+).

Acts on the nodes on and beyond the face (global index <= 0 for a '-' side,
>= ncells for a '+' side), with n the unit normal pointing into the domain and
v_n = v . n the normal grid velocity:

- ``fixed``: v = 0 (no slip);
- ``slip``: if v_n < 0 the normal component is removed (free to separate);
- ``friction``: if v_n < 0 the normal component is removed and the tangential
  velocity v_t is reduced by mu |v_n|, never reversed:
  v_t <- v_t max(0, 1 - mu |v_n| / |v_t|)  (Coulomb friction in velocity form,
  Bardenhagen, Brackbill & Sulsky 2000, Comput. Methods Appl. Mech. Eng. 187:529).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numba import njit
from pydantic import Field

from ..plugin import Params
from ..stages import GridStage

SIDES = ("x-", "x+", "y-", "y+", "z-", "z+")
CONDITIONS = {"fixed": 0, "slip": 1, "friction": 2}


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
                if g_mass[idx] <= 0.0:
                    continue
                vn = g_vel[idx, axis] * normal
                if condition == 0:
                    for a in range(d):
                        g_vel[idx, a] = 0.0
                elif vn < 0.0:
                    g_vel[idx, axis] = 0.0
                    if condition == 2:
                        vt = 0.0
                        for a in range(d):
                            vt += g_vel[idx, a] * g_vel[idx, a]
                        vt = np.sqrt(vt)
                        if vt > 0.0:
                            scale = max(0.0, 1.0 - mu * (-vn) / vt)
                            for a in range(d):
                                g_vel[idx, a] *= scale


class Wall(GridStage):
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
        self.normal = 1.0 if minus else -1.0
        self.first, self.last = (-(1 << 40), 0) if minus else (n, 1 << 40)
        self.condition = CONDITIONS[self.params.condition]

    def apply_grid(self, view, dt, time, remap):
        wall_apply(view.g_vel, view.g_mass, view.lo, view.nloc, self.axis, self.normal,
                   self.first, self.last, self.condition, self.params.friction)
