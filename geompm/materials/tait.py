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
from typing import Literal

from numba import njit
from pydantic import Field

from geompm.materials.base import Material, MaterialParams
from geompm.contract.layout import param_layout

#: the first slots of every Tait-EOS law; shear_modulus [Pa] is 0 except under the elasto-viscoplastic
#: integration (fluid.py)
EOS = param_layout("density", "sound_speed", "eos_exponent", "shear_modulus")


@njit(cache=True, inline="always")
def tait_pressure(rho, rho0, c, r):
    return rho0 * c * c / r * ((rho / rho0) ** r - 1.0)


@njit(cache=True)
def tait_wave_speed(prm, rho):
    """Acoustic speed max(c, c sqrt((rho/rho0)^(r-1))) [m/s] of one particle of a law whose layout
    starts with EOS (never below c: the CFL step is set by the reference sound speed at least); with a
    shear modulus G (the elasto-viscoplastic integration) the P-wave speed sqrt(c_a^2 + 4 G / (3 rho0)),
    G over the reference density so that the speed stays monotone in rho (cpu_loops.py)."""
    c = prm[EOS.sound_speed]
    ca = max(c, c * math.sqrt((rho / prm[EOS.density]) ** (prm[EOS.eos_exponent] - 1.0)))
    G = prm[EOS.shear_modulus]
    if G > 0.0:
        return math.sqrt(ca * ca + 4.0 * G / (3.0 * prm[EOS.density]))
    return ca


@njit(cache=True, inline="always")
def eos_pressure(prm, rho):
    """Tait pressure [Pa] of one particle for a law whose layout starts with EOS."""
    return tait_pressure(rho, prm[EOS.density], prm[EOS.sound_speed], prm[EOS.eos_exponent])


class TaitFluid(Material):
    """Base of the weakly compressible fluid laws (params density, sound_speed, eos_exponent)."""

    rate_dependent = True
    fluid = True
    particle_wave_speed = tait_wave_speed

    @staticmethod
    def pack_eos(params, shear_modulus: float = 0.0, **law_params) -> dict:
        """The EOS slots followed by the law's own (by name)."""
        return {"density": params.density, "sound_speed": params.sound_speed,
                "eos_exponent": params.eos_exponent, "shear_modulus": shear_modulus, **law_params}

    def k0(self) -> float:
        return 1.0

    def stiffness(self) -> float:
        """EOS stiffness rho0 c^2 [Pa] (bulk modulus at rest), used as E by artificial damping."""
        return float(self.params.density * self.params.sound_speed ** 2)


class YieldFluidParams(MaterialParams):
    """The EOS and integration parameters of the yield-stress fluids (bingham, cross, herschel_bulkley)."""

    sound_speed: float = Field(gt=0, description="Artificial sound speed c of the Tait EOS [m/s]")
    eos_exponent: float = Field(7.0, ge=1.0, le=15.0, description="Exponent r of the Tait EOS [-]")
    integration: Literal["explicit", "elastoviscoplastic"] = Field(
        "explicit", description="'explicit': the source's viscous stress (time step bounded by the viscous limit); "
        "'elastoviscoplastic': Maxwell relaxation of a deviatoric stress with shear modulus G (CFL limit only)")
    shear_modulus: float | None = Field(
        None, gt=0, description="G [Pa] of the elasto-viscoplastic integration; default rho0 c^2 / 4")


class YieldFluid(TaitFluid):
    """Base of the yield-stress fluids: the integration option and the viscous limit it implies."""

    @staticmethod
    def evp_shear_modulus(p) -> float:
        """G [Pa] of params ``p`` under the elasto-viscoplastic integration, 0 under the explicit one.  The
        default rho0 c^2 / 4 raises the wave speed by sqrt(4/3), 15 %, and gives a Maxwell relaxation
        time mu / G that is 4 mu / (rho0 c^2): e.g. 1.7e-5 s for mu = 1 Pa s, rho0 = 2000 kg/m3, c = 10 m/s."""
        if p.integration != "elastoviscoplastic":
            return 0.0
        return float(p.shear_modulus if p.shear_modulus is not None else 0.25 * p.density * p.sound_speed ** 2)

    @classmethod
    def pack_yield_fluid(cls, p, **law_params) -> dict:
        return cls.pack_eos(p, shear_modulus=cls.evp_shear_modulus(p), **law_params)

    def largest_viscosity(self) -> float:
        """The largest effective viscosity the law takes [Pa s]."""
        raise NotImplementedError

    def alternatives(self):
        """The law under the other integration (the time-step report of `geompm validate`)."""
        other = "explicit" if self.params.integration == "elastoviscoplastic" else "elastoviscoplastic"
        return [(f'"integration": "{other}"', type(self)(self.params.model_copy(update={"integration": other})))]

    def kinematic_viscosity(self) -> float:
        """nu [m2/s] of the explicit viscous limit; 0 under the elasto-viscoplastic integration, whose
        implicit Maxwell relaxation is stable at any step (fluid.py)."""
        if self.params.integration == "elastoviscoplastic":
            return 0.0
        return float(self.largest_viscosity() / self.params.density)
