"""Bingham viscoplastic fluid, weakly compressible (eqs. 1-5 of the source study).

    tau = mu_eff epsdot',  mu_eff = mu_B + tau_B / gamma_dot          (1)-(3)
    sigma = -P I + tau,    P = rho0 c^2 / r ((rho/rho0)^r - 1)         (4)-(5)

Regularisation (Papanastasiou 1987, J. Rheol. 31:385), so that mu_eff never
divides by zero:

    mu_eff = mu_B + tau_B (1 - exp(-M gamma_dot)) / gamma_dot,

with M = ``regularisation_time`` [s]; mu_eff -> mu_B + tau_B M as
gamma_dot -> 0 and equals the Bingham value within a factor exp(-M gamma_dot)
of the yield term above gamma_dot ~ 5 / M.  gamma_dot = sqrt(2 D':D') (fluid.py).
The zero-rate viscosity mu_B + tau_B M sets the viscous time-step limit of the
explicit integration; "integration": "elastoviscoplastic" removes it (fluid.py).
"""

from __future__ import annotations

import math

from numba import njit
from pydantic import Field

from geompm.materials.fluid import evp_yield_stress, set_fluid_stress, shear_rate
from geompm.contract.layout import param_layout
from geompm.materials.tait import EOS, YieldFluid, YieldFluidParams, eos_pressure

#: packed parameters: EOS, mu_B [Pa s], tau_B [Pa], M [s]
BINGHAM = param_layout(EOS, "viscosity", "yield_stress", "regularisation_time")


class BinghamParams(YieldFluidParams):
    viscosity: float = Field(gt=0, description="Plastic (Bingham) viscosity mu_B [Pa s]")
    yield_stress: float = Field(ge=0, description="Bingham yield stress tau_B [Pa]")
    regularisation_time: float = Field(
        100.0, gt=0, description="Papanastasiou parameter M [s]; larger is closer to ideal Bingham")


@njit(cache=True, inline="always")
def bingham_viscosity(gdot, mu_b, tau_b, m):
    x = m * gdot
    if x < 1e-8:  # series of (1 - exp(-x)) / gdot = m (1 - x/2 + ...)
        return mu_b + tau_b * m * (1.0 - 0.5 * x)
    return mu_b + tau_b * (1.0 - math.exp(-x)) / gdot


@njit(fastmath=True, cache=True)
def bingham_stress(prm, dt, L, rho, s, state):
    """One particle's regularised Bingham stress; s (6,) and state (1,) in place."""
    gdot = shear_rate(L)
    G = prm[EOS.shear_modulus]
    if G > 0.0:  # elasto-viscoplastic: the ideal yield surface, no regularisation needed
        evp_yield_stress(s, L, eos_pressure(prm, rho), dt, G, prm[BINGHAM.yield_stress], prm[BINGHAM.viscosity], 1.0)
    else:
        mu = bingham_viscosity(gdot, prm[BINGHAM.viscosity], prm[BINGHAM.yield_stress],
                               prm[BINGHAM.regularisation_time])
        set_fluid_stress(s, L, eos_pressure(prm, rho), mu)
    state[0] = gdot


class Bingham(YieldFluid):
    name = "bingham"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Bingham viscoplastic fluid (Papanastasiou-regularised) with Tait EOS pressure"
    Params = BinghamParams
    state_vars = ("shear_rate",)
    layout = BINGHAM
    particle_stress = bingham_stress

    @classmethod
    def pack(cls, p):
        return cls.pack_yield_fluid(p, viscosity=p.viscosity, yield_stress=p.yield_stress,
                            regularisation_time=p.regularisation_time)

    @classmethod
    def example_params(cls):
        return cls.Params(density=2000.0, viscosity=1.0, yield_stress=50.0, sound_speed=30.0)

    def largest_viscosity(self) -> float:
        p = self.params
        return p.viscosity + p.yield_stress * p.regularisation_time
