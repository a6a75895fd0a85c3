"""Weakly compressible equation of state (Tait form as used by Monaghan 1994).

P = rho0 c^2 / r * ((rho / rho0)^r - 1)            [Pa]
dP/drho = c^2 (rho / rho0)^(r - 1)   -> acoustic speed c_eff = sqrt(dP/drho)

rho0 reference density [kg/m3], c artificial sound speed [m/s] (choose >= 10x
the largest flow speed for density variations below 1%), r exponent (7 for
water).  Monaghan, J.J. (1994) Simulating free surface flows with SPH, J.
Comput. Phys. 110:399-406; eq. (5) of the source study.

``TaitFluid`` is the base of every law whose pressure comes from this EOS
(newtonian, bingham, cross): their parameter layouts start with ``EOS``
(density rho0, sound_speed c, eos_exponent r), which gives them one
wave-speed function, K0 = 1 (hydrostatic) and the stiffness rho0 c^2 that
artificial damping uses as E.
"""

import math

from numba import njit

from .base import Material
from ..layout import param_layout

#: the first slots of every Tait-EOS law
EOS = param_layout("density", "sound_speed", "eos_exponent")


@njit(cache=True, inline="always")
def tait_pressure(rho, rho0, c, r):
    return rho0 * c * c / r * ((rho / rho0) ** r - 1.0)


@njit(cache=True)
def tait_wave_speed(prm, rho):
    """Acoustic speed max(c, c sqrt((rho/rho0)^(r-1))) [m/s] of one particle of a law whose layout
    starts with EOS (never below c: the CFL step is set by the reference sound speed at least)."""
    c = prm[EOS.sound_speed]
    return max(c, c * math.sqrt((rho / prm[EOS.density]) ** (prm[EOS.eos_exponent] - 1.0)))


@njit(cache=True, inline="always")
def eos_pressure(prm, rho):
    """Tait pressure [Pa] of one particle for a law whose layout starts with EOS."""
    return tait_pressure(rho, prm[EOS.density], prm[EOS.sound_speed], prm[EOS.eos_exponent])


class TaitFluid(Material):
    """Base of the weakly compressible fluid laws (params density, sound_speed, eos_exponent)."""

    rate_dependent = True
    particle_wave_speed = tait_wave_speed

    @staticmethod
    def pack_eos(params, **law_params) -> dict:
        """The EOS slots followed by the law's own (by name)."""
        return {"density": params.density, "sound_speed": params.sound_speed,
                "eos_exponent": params.eos_exponent, **law_params}

    def k0(self) -> float:
        return 1.0

    def stiffness(self) -> float:
        """EOS stiffness rho0 c^2 [Pa] (bulk modulus at rest), used as E by artificial damping."""
        return float(self.params.density * self.params.sound_speed ** 2)
