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

With ``reference_cell_size`` h_ref set, h_ref replaces h in zeta_d: the rate is
the one the source's law gives at h_ref, whatever the cell size, so a mesh study
refines the discretisation without strengthening the damping (at a fixed xi,
zeta_d doubles at each halving of h; docs/validation/seed-inclined-flow.md).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from pydantic import Field

from geompm.contract.plugin import Params
from geompm.contract.stages import DAMPING, NO_AUX, ParticleStage


class ArtificialParams(Params):
    xi: float = Field(gt=0, le=1.0, description="Dimensionless damping coefficient xi [-] (source: 0.001-0.002)")
    materials: list[str] | None = Field(None, description="Materials damped (default: all)")
    reference_cell_size: float | None = Field(
        None, gt=0, description="h_ref [m]: if set, zeta = xi/h_ref sqrt(E/rho) at every cell size (a rate that does "
                                "not grow as the grid is refined); default: the grid's cell size (source eq. 8)")


@njit(cache=True, inline="always")
def scale_velocity(prm, aux, dt, k, x, x0, v, C, m, s, work, out):
    """v <- v exp(-zeta_k dt), and C with it; prm[k] holds the factor exp(-zeta_k dt) of block k."""
    factor = prm[k]
    d = v.shape[0]
    for a in range(d):
        v[a] *= factor
        for b in range(d):
            C[a, b] *= factor


class ArtificialDamping(ParticleStage):
    holds_step = True  # its parameters follow the step and the time alone (engine/held_step.py)
    name = "artificial"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Linear artificial damping f = -zeta m v, zeta = xi/h sqrt(E/rho) (source eqs. 7-8)"
    Params = ArtificialParams
    phase = DAMPING
    particle_rule = scale_velocity

    @classmethod
    def check(cls, params, case):
        unknown = [m for m in params.materials or [] if m not in case.materials]
        return [("materials", f"no material named {', '.join(unknown)}")] if unknown else []

    def setup(self, scene):
        names = self.params.materials or scene.material_names
        self.zeta = np.zeros(len(scene.materials))  # [1/s] per material block
        h = self.params.reference_cell_size or scene.grid.h
        for k, (name, mat) in enumerate(zip(scene.material_names, scene.materials)):
            if name in names:
                self.zeta[k] = self.params.xi / h * math.sqrt(mat.stiffness() / mat.density)
        self.factor = np.ones(len(scene.materials))

    def particle_blocks(self, nblocks):
        return [k for k in range(nblocks) if self.zeta[k] > 0.0]

    def refines_with_the_grid(self) -> str:
        if self.params.reference_cell_size is not None:
            return ""
        return (f"{self.json_path}: the damping rate xi/h sqrt(E/rho) doubles at each halving of the cell size, so "
                "the variants damp the flow differently (a flow to a barrier slows as h falls); set "
                "\"reference_cell_size\" to fix the rate (docs/impact-forces.md)")

    def particle_reach(self, prm, lo, hi):
        return lo, hi  # velocities only: the particles stay where they are

    def particle_args(self, dt, time):
        # the per-block factors, one slot per material block (the layout is the case's material order)
        np.exp(-self.zeta * dt, out=self.factor)
        return self.factor, NO_AUX
