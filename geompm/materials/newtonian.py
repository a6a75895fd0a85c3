"""Weakly compressible Newtonian fluid.

    sigma = -P I + 2 mu (D - tr(D)/3 I)
    P = rho0 c^2 / r ((rho / rho0)^r - 1)        (Tait EOS, see tait.py)

mu dynamic viscosity [Pa s], D = sym(L) [1/s].  The stress is computed anew
from the current density and rate each step (no stress history), so it is
objective by construction.  Viscous time-step limit dt <= rho h^2 / (2 d mu).
"""

from __future__ import annotations

from numba import njit, prange
from pydantic import Field

from .base import MaterialParams
from .fluid import set_fluid_stress
from .tait import TaitFluid, tait_pressure


class NewtonianParams(MaterialParams):
    viscosity: float = Field(ge=0, description="Dynamic viscosity mu [Pa s]")
    sound_speed: float = Field(gt=0, description="Artificial sound speed c of the Tait EOS [m/s]")
    eos_exponent: float = Field(7.0, ge=1.0, le=15.0, description="Exponent r of the Tait EOS [-]")


@njit(parallel=True, fastmath=True, cache=True)
def _stress(prm, dt, p_L, p_rho, p_stress, p_state):
    rho0, c, r, mu = prm[0], prm[1], prm[2], prm[3]
    for p in prange(p_L.shape[0]):
        L = p_L[p]
        s = p_stress[p]
        set_fluid_stress(s, L, tait_pressure(p_rho[p], rho0, c, r), mu)


class Newtonian(TaitFluid):
    name = "newtonian"
    description = "Weakly compressible Newtonian fluid: Tait EOS pressure plus viscous stress"
    Params = NewtonianParams
    stress_kernel = _stress

    @classmethod
    def pack(cls, params):
        return cls.pack_eos(params, params.viscosity)

    @classmethod
    def example_params(cls):
        return cls.Params(density=1000.0, viscosity=1.0e-3, sound_speed=35.0)

    def kinematic_viscosity(self) -> float:
        return float(self.params.viscosity / self.params.density)
