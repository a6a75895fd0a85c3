"""Weakly compressible Newtonian fluid.

    sigma = -P I + 2 mu (D - tr(D)/3 I)
    P = rho0 c^2 / r ((rho / rho0)^r - 1)        (Tait EOS, see tait.py)

mu dynamic viscosity [Pa s], D = sym(L) [1/s].  The stress is computed anew
from the current density and rate each step (no stress history), so it is
objective by construction.  Viscous time-step limit dt <= rho h^2 / (2 d mu).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange
from pydantic import Field

from .base import Material, MaterialParams
from .tait import tait_pressure, tait_wave_speed


class NewtonianParams(MaterialParams):
    viscosity: float = Field(ge=0, description="Dynamic viscosity mu [Pa s]")
    sound_speed: float = Field(gt=0, description="Artificial sound speed c of the Tait EOS [m/s]")
    eos_exponent: float = Field(7.0, ge=1.0, le=15.0, description="Exponent r of the Tait EOS [-]")


@njit(parallel=True, fastmath=True, cache=True)
def _stress(prm, dt, p_L, p_rho, p_stress, p_state):
    rho0, mu, c, r = prm[0], prm[1], prm[2], prm[3]
    for p in prange(p_L.shape[0]):
        L = p_L[p]
        s = p_stress[p]
        P = tait_pressure(p_rho[p], rho0, c, r)
        tr3 = (L[0, 0] + L[1, 1] + L[2, 2]) / 3.0
        s[0] = -P + 2.0 * mu * (L[0, 0] - tr3)
        s[1] = -P + 2.0 * mu * (L[1, 1] - tr3)
        s[2] = -P + 2.0 * mu * (L[2, 2] - tr3)
        s[3] = mu * (L[0, 1] + L[1, 0])
        s[4] = mu * (L[1, 2] + L[2, 1])
        s[5] = mu * (L[0, 2] + L[2, 0])


@njit(cache=True)
def _wave_speed(prm, p_rho):
    return tait_wave_speed(prm[0], prm[2], prm[3], p_rho)


class Newtonian(Material):
    name = "newtonian"
    description = "Weakly compressible Newtonian fluid: Tait EOS pressure plus viscous stress"
    Params = NewtonianParams
    rate_dependent = True
    stress_kernel = _stress
    wave_speed_kernel = _wave_speed

    @classmethod
    def pack(cls, params):
        return np.array([params.density, params.viscosity, params.sound_speed, params.eos_exponent])

    def k0(self) -> float:
        return 1.0

    def stiffness(self) -> float:
        """EOS stiffness rho0 c^2 [Pa] (bulk modulus at rest), used as E by damping."""
        return float(self.params.density * self.params.sound_speed ** 2)

    def kinematic_viscosity(self) -> float:
        return float(self.params.viscosity / self.params.density)
