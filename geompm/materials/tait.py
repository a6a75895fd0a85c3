"""Weakly compressible equation of state (Tait form as used by Monaghan 1994).

P = rho0 c^2 / r * ((rho / rho0)^r - 1)            [Pa]
dP/drho = c^2 (rho / rho0)^(r - 1)   -> acoustic speed c_eff = sqrt(dP/drho)

rho0 reference density [kg/m3], c artificial sound speed [m/s] (choose >= 10x
the largest flow speed for density variations below 1%), r exponent (7 for
water).  Monaghan, J.J. (1994) Simulating free surface flows with SPH, J.
Comput. Phys. 110:399-406; eq. (5) of the source study.
"""

import math

from numba import njit, prange


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
