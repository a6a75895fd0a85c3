"""Weakly compressible equation of state (Tait form as used by Monaghan 1994).

P = rho0 c^2 / r * ((rho / rho0)^r - 1)            [Pa]
dP/drho = c^2 (rho / rho0)^(r - 1)   -> acoustic speed c_eff = sqrt(dP/drho)

rho0 reference density [kg/m3], c artificial sound speed [m/s] (choose >= 10x
the largest flow speed for density variations below 1%), r exponent (7 for
water).  Monaghan, J.J. (1994) Simulating free surface flows with SPH, J.
Comput. Phys. 110:399-406; eq. (5) of the source study.

``TaitFluid`` is the base of every law whose pressure comes from this EOS
(newtonian, bingham, cross): their packed parameters start with
[rho0, c, r], which gives them one wave-speed kernel, K0 = 1 (hydrostatic)
and the stiffness rho0 c^2 that artificial damping uses as E.
"""

import math

import numpy as np
from numba import njit, prange

from .base import Material


@njit(cache=True, inline="always")
def tait_pressure(rho, rho0, c, r):
    return rho0 * c * c / r * ((rho / rho0) ** r - 1.0)


@njit(parallel=True, cache=True)
def tait_wave_speed(rho0, c, r, p_rho):
    """max over particles of c sqrt((rho/rho0)^(r-1)) [m/s]."""
    cmax = c
    for p in prange(p_rho.shape[0]):
        cmax = max(cmax, c * math.sqrt((p_rho[p] / rho0) ** (r - 1.0)))
    return cmax


@njit(cache=True)
def tait_wave_speed_kernel(prm, p_rho):
    """Wave speed of a law packed as [rho0, c, r, ...]."""
    return tait_wave_speed(prm[0], prm[1], prm[2], p_rho)


class TaitFluid(Material):
    """Base of the weakly compressible fluid laws (params density, sound_speed, eos_exponent)."""

    rate_dependent = True
    wave_speed_kernel = tait_wave_speed_kernel

    @staticmethod
    def pack_eos(params, *law_params):
        """[rho0, c, r, *law_params] as float64."""
        return np.array([params.density, params.sound_speed, params.eos_exponent, *law_params], dtype=float)

    def k0(self) -> float:
        return 1.0

    def stiffness(self) -> float:
        """EOS stiffness rho0 c^2 [Pa] (bulk modulus at rest), used as E by artificial damping."""
        return float(self.params.density * self.params.sound_speed ** 2)
