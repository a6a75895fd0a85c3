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
from .fluid import set_fluid_stress
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
        set_fluid_stress(s, L, tait_pressure(p_rho[p], rho0, c, r), mu)


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

    @classmethod
    def example_params(cls):
        return cls.Params(density=1000.0, viscosity=1.0e-3, sound_speed=35.0)

    def k0(self) -> float:
        return 1.0

    def stiffness(self) -> float:
        """EOS stiffness rho0 c^2 [Pa] (bulk modulus at rest), used as E by damping."""
        return float(self.params.density * self.params.sound_speed ** 2)

    def kinematic_viscosity(self) -> float:
        return float(self.params.viscosity / self.params.density)
