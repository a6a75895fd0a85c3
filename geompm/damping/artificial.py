"""Linear artificial damping on particles (eqs. 7-8 of the source study).

    f_p = -zeta_d m_p v_p,     zeta_d = (xi / h) sqrt(E / rho)          [1/s]

xi is dimensionless and h the cell size: dx in 1D, sqrt(dx dy) in 2D,
cbrt(dx dy dz) in 3D, which for geompm's square/cubic cells is the cell size
in every dimension.  E is the material's stiffness: Young's modulus for solids
and the EOS stiffness rho0 c^2 for the fluid laws (Tait), rho its reference
density; so each material gets its own zeta_d.  The force is integrated
exactly over a step, v_p <- v_p exp(-zeta_d dt) (and the APIC matrix C_p with
it, since it is part of the particle's velocity field), which is stable for
any zeta_d dt.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange
from pydantic import Field

from ..plugin import Params
from ..stages import DAMPING, ParticleStage


class ArtificialParams(Params):
    xi: float = Field(gt=0, le=1.0, description="Dimensionless damping coefficient xi [-] (source: 0.001-0.002)")
    materials: list[str] | None = Field(None, description="Materials damped (default: all)")


@njit(parallel=True, cache=True)
def scale_velocity(p_v, p_C, start, end, factor):
    d = p_v.shape[1]
    for p in prange(start, end):
        for a in range(d):
            p_v[p, a] *= factor
            for b in range(d):
                p_C[p, a, b] *= factor


class ArtificialDamping(ParticleStage):
    name = "artificial"
    description = "Linear artificial damping f = -zeta m v, zeta = xi/h sqrt(E/rho) (source eqs. 7-8)"
    Params = ArtificialParams
    phase = DAMPING

    @classmethod
    def check(cls, params, case):
        unknown = [m for m in params.materials or [] if m not in case.materials]
        return [("materials", f"no material named {', '.join(unknown)}")] if unknown else []

    def setup(self, scene):
        names = self.params.materials or scene.material_names
        self.zeta = np.zeros(len(scene.materials))
        for k, (name, mat) in enumerate(zip(scene.material_names, scene.materials)):
            if name in names:
                self.zeta[k] = self.params.xi / scene.grid.h * math.sqrt(mat.stiffness() / mat.density)

    def apply_particles(self, state, dt, time):
        for k, (s, e) in enumerate(state.blocks):
            if self.zeta[k] > 0.0 and e > s:
                scale_velocity(state.p_v, state.p_C, s, e, math.exp(-self.zeta[k] * dt))
