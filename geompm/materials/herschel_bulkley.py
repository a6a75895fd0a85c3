"""Herschel-Bulkley viscoplastic fluid, weakly compressible (explicit viscous integration).

    |tau| = tau_y + K gamma_dot^n   beyond yield    (Herschel & Bulkley 1926, Kolloid-Z. 39:291)
    mu_eff = K gamma_dot^(n-1) + tau_y (1 - exp(-M gamma_dot)) / gamma_dot,   mu_eff <= mu_max
    sigma = -P I + mu_eff epsdot',  P = rho0 c^2 / r ((rho/rho0)^r - 1)   (the Tait EOS, tait.py)

K the consistency [Pa s^n], n the flow index (n < 1 shear thinning, n = 1
Bingham, n > 1 shear thickening), tau_y the yield stress [Pa]; the yield
term is Papanastasiou-regularised (1987, J. Rheol. 31:385) with
``regularisation_time`` M [s], as in bingham.py: within a factor exp(-M
gamma_dot) of the ideal law, so within 1 % for gamma_dot >= 4.6 / M.  For
n < 1 the power-law viscosity K gamma_dot^(n-1) grows without bound as
gamma_dot -> 0, for n > 1 as gamma_dot grows, so mu_eff is capped at
``max_viscosity`` mu_max [Pa s] (required for n != 1, optional for n = 1);
gamma_dot = sqrt(2 D':D') (fluid.py).

The largest viscosity the law can take, min(mu_max, tau_y M + K) for n = 1
and mu_max otherwise, sets the explicit viscous time-step limit
dt <= rho h^2 / (2 d mu_max) (backend/timestep.py).  Debris-flow practice uses
this rheology for muds (Coussot 1997, Mudflow Rheology and Dynamics).
"""

from __future__ import annotations

import math

from numba import njit
from pydantic import Field, model_validator

from geompm.contract.layout import param_layout
from geompm.materials.fluid import evp_yield_stress, set_fluid_stress, shear_rate
from geompm.materials.tait import EOS, YieldFluid, YieldFluidParams, eos_pressure

#: packed parameters: EOS, K [Pa s^n], n [-], tau_y [Pa], M [s], mu_max [Pa s] (inf: no cap)
HB = param_layout(EOS, "consistency", "flow_index", "yield_stress", "regularisation_time", "max_viscosity")


class HerschelBulkleyParams(YieldFluidParams):
    consistency: float = Field(gt=0, description="Consistency K [Pa s^n]")
    flow_index: float = Field(gt=0.05, le=2.0, description="Flow index n [-] (1: Bingham)")
    yield_stress: float = Field(ge=0, description="Yield stress tau_y [Pa]")
    regularisation_time: float = Field(
        100.0, gt=0, description="Papanastasiou parameter M [s]; larger is closer to the ideal yield stress")
    max_viscosity: float | None = Field(
        None, gt=0, description="Cap mu_max on the effective viscosity [Pa s]; required for flow_index != 1")

    @model_validator(mode="after")
    def _cap_for_thinning(self):
        if self.flow_index != 1.0 and self.max_viscosity is None:
            raise ValueError("flow_index != 1 needs max_viscosity [Pa s]: K gamma_dot^(n-1) is unbounded as "
                             "gamma_dot -> 0 (n < 1) or as gamma_dot grows (n > 1), and the explicit time step "
                             "needs its bound (e.g. 1e3 to 1e4 times K)")
        return self


@njit(cache=True, inline="always")
def hb_viscosity(gdot, K, n, tau_y, M, mu_max):
    x = M * gdot
    if x < 1e-8:  # (1 - exp(-x)) / gdot = M (1 - x/2 + ...)
        yield_part = tau_y * M * (1.0 - 0.5 * x)
    else:
        yield_part = tau_y * (1.0 - math.exp(-x)) / gdot
    if gdot > 0.0:
        power = K * gdot ** (n - 1.0)
    elif n == 1.0:
        power = K
    elif n > 1.0:
        power = 0.0
    else:
        power = mu_max
    return min(mu_max, power + yield_part)


@njit(fastmath=True, cache=True)
def hb_stress(prm, dt, L, rho, s, state):
    """One particle's Herschel-Bulkley stress; s (6,) and state (2,) in place."""
    gdot = shear_rate(L)
    G = prm[HB.shear_modulus]
    P = eos_pressure(prm, rho)
    if G > 0.0:  # elasto-viscoplastic: the ideal yield surface, no regularisation or cap needed
        gp = evp_yield_stress(s, L, P, dt, G, prm[HB.yield_stress], prm[HB.consistency], prm[HB.flow_index])
        mu = (prm[HB.yield_stress] + prm[HB.consistency] * gp ** prm[HB.flow_index]) / gp if gp > 0.0 else math.inf
    else:
        mu = hb_viscosity(gdot, prm[HB.consistency], prm[HB.flow_index], prm[HB.yield_stress],
                          prm[HB.regularisation_time], prm[HB.max_viscosity])
        set_fluid_stress(s, L, P, mu)
    state[0] = gdot
    state[1] = mu


class HerschelBulkley(YieldFluid):
    name = "herschel_bulkley"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Herschel-Bulkley viscoplastic fluid tau = tau_y + K gamma_dot^n (regularised), Tait EOS"
    Params = HerschelBulkleyParams
    state_vars = ("shear_rate", "effective_viscosity")
    layout = HB
    particle_stress = hb_stress

    @classmethod
    def pack(cls, p):
        cap = math.inf if p.max_viscosity is None else p.max_viscosity
        return cls.pack_yield_fluid(p, consistency=p.consistency, flow_index=p.flow_index, yield_stress=p.yield_stress,
                            regularisation_time=p.regularisation_time, max_viscosity=cap)

    @classmethod
    def example_params(cls):
        return cls.Params(density=1800.0, consistency=5.0, flow_index=0.5, yield_stress=50.0, max_viscosity=1e4,
                          sound_speed=30.0)

    def largest_viscosity(self) -> float:
        """The largest mu_eff the law takes [Pa s]: what the explicit viscous limit uses."""
        p = self.params
        if p.flow_index != 1.0:
            return p.max_viscosity
        cap = math.inf if p.max_viscosity is None else p.max_viscosity
        return min(cap, p.yield_stress * p.regularisation_time + p.consistency)

