"""Generalized Cross fluid, weakly compressible (eq. 6 of the source study).

    mu_eff = (mu_0 + (A gamma_dot)^m mu_inf) / (1 + (A gamma_dot)^m)       (6)
    sigma = -P I + mu_eff epsdot',  P = rho0 c^2 / r ((rho/rho0)^r - 1)

mu_0, mu_inf low- and high-shear-rate viscosities [Pa s], A a time constant
[s] (the source's K), m [-]; gamma_dot = sqrt(2 D':D') (fluid.py).  Cross
(1965) J. Colloid Sci. 20:417.  The source uses Cross instead of Bingham
because mu_eff stays bounded by mu_0 as gamma_dot -> 0.

``from_bingham: {viscosity: mu_B, yield_stress: tau_B}`` applies the source's
mapping mu_inf = mu_B, mu_0 = 10000 mu_inf, A = mu_0 / tau_B, m = 1.  With it
the Cross shear stress differs from Bingham's by exactly
-(tau_B + mu_B gamma_dot) / (1 + A gamma_dot), i.e. a relative error
-1 / (1 + A gamma_dot): under 5% for gamma_dot >= 19 tau_B / mu_0
(tests/verification/test_fluid_laws.py).  mu_0 sets the viscous time-step limit
dt <= rho h^2 / (2 d mu_0), which is small: see docs/materials.md.
"""

from __future__ import annotations

import math

from numba import njit
from pydantic import Field, model_validator

from geompm.contract.plugin import Params
from geompm.materials.fluid import equivalent_shear, evp_trial, set_fluid_stress, set_scaled_trial, shear_rate
from geompm.contract.layout import param_layout
from geompm.materials.tait import EOS, YieldFluid, YieldFluidParams, eos_pressure

#: packed parameters: EOS, mu_0 and mu_inf [Pa s], A [s], m [-]
CROSS = param_layout(EOS, "viscosity_zero", "viscosity_infinity", "time_constant", "rate_exponent")


class BinghamMapping(Params):
    viscosity: float = Field(gt=0, description="Bingham viscosity mu_B [Pa s] -> mu_inf")
    yield_stress: float = Field(gt=0, description="Bingham yield stress tau_B [Pa] -> A = mu_0 / tau_B")


class CrossParams(YieldFluidParams):
    viscosity_zero: float | None = Field(None, gt=0, description="Low-shear-rate viscosity mu_0 [Pa s]")
    viscosity_infinity: float | None = Field(None, ge=0, description="High-shear-rate viscosity mu_inf [Pa s]")
    time_constant: float | None = Field(None, gt=0, description="Cross time constant A (K in the source) [s]")
    rate_exponent: float = Field(1.0, gt=0, le=2.0, description="Cross exponent m [-]")
    from_bingham: BinghamMapping | None = Field(
        None, description="Derive mu_inf, mu_0, A, m from Bingham parameters (source's mapping)")

    @model_validator(mode="after")
    def _resolve(self):
        direct = (self.viscosity_zero, self.viscosity_infinity, self.time_constant)
        if self.from_bingham is not None:
            if any(v is not None for v in direct):
                raise ValueError("give either 'from_bingham' or viscosity_zero/viscosity_infinity/time_constant")
            mu_inf = self.from_bingham.viscosity
            self.viscosity_infinity = mu_inf
            self.viscosity_zero = 1e4 * mu_inf
            self.time_constant = self.viscosity_zero / self.from_bingham.yield_stress
            self.rate_exponent = 1.0
        elif any(v is None for v in direct):
            raise ValueError("needs viscosity_zero, viscosity_infinity and time_constant (or from_bingham)")
        elif self.viscosity_infinity > self.viscosity_zero:
            raise ValueError("viscosity_infinity must not exceed viscosity_zero (shear thinning)")
        return self


@njit(cache=True, inline="always")
def cross_viscosity(gdot, mu0, mu_inf, A, m):
    x = (A * gdot) ** m
    return (mu0 + x * mu_inf) / (1.0 + x)


@njit(cache=True, inline="always")
def cross_plastic_rate(q_tr, gdt, mu0, mu_inf, A, m):
    """The viscous shear rate gp [1/s] of the elasto-viscoplastic return, the root of
    q_tr - G dt gp = mu_eff(gp) gp: the viscosity is taken at the rate of the viscous element, not at
    the total rate, so that a particle loading elastically (gp << gamma_dot) keeps mu_0.  m = 1 (the
    source's mapping) gives a quadratic, A (G dt + mu_inf) gp^2 + (G dt + mu_0 - A q_tr) gp - q_tr = 0,
    solved in the cancellation-free form; other m by bisection on [0, q_tr / (G dt)]."""
    if m == 1.0:
        a = A * (gdt + mu_inf)
        b = gdt + mu0 - A * q_tr
        disc = math.sqrt(b * b + 4.0 * a * q_tr)
        return 2.0 * q_tr / (b + disc) if b > 0.0 else (disc - b) / (2.0 * a)
    lo = 0.0
    hi = q_tr / gdt
    for _ in range(64):
        gp = 0.5 * (lo + hi)
        if gdt * gp + cross_viscosity(gp, mu0, mu_inf, A, m) * gp > q_tr:
            hi = gp
        else:
            lo = gp
    return 0.5 * (lo + hi)


@njit(cache=True, inline="always")
def evp_cross_stress(s, L, P, dt, G, mu0, mu_inf, A, m):
    """Elasto-viscoplastic Cross update, s <- -P I + tau_tr (q_tr - G dt gp) / q_tr (Voigt, in place), the
    backward-Euler step of the Maxwell model dtau/dt = 2 G D' - (G / mu_eff(gp)) tau with the viscosity at
    the viscous rate gp (cross_plastic_rate); for a constant mu it is tau_tr / (1 + G dt / mu), and its
    steady state under a constant rate is the viscous law tau = 2 mu_eff D' (Yue et al. 2015, ACM TOG
    34(5):160).  Returns gp."""
    t = evp_trial(s, L, dt, G)
    q_tr = equivalent_shear(t)
    if q_tr <= 0.0:
        set_scaled_trial(s, t, 1.0, P)
        return 0.0
    gdt = G * dt
    gp = cross_plastic_rate(q_tr, gdt, mu0, mu_inf, A, m)
    set_scaled_trial(s, t, (q_tr - gdt * gp) / q_tr, P)
    return gp


@njit(fastmath=True, cache=True)
def cross_stress(prm, dt, L, rho, s, state):
    """One particle's Cross stress (eq. 6); s (6,) and state (2,) in place."""
    gdot = shear_rate(L)
    mu0, mu_inf, A, m = (prm[CROSS.viscosity_zero], prm[CROSS.viscosity_infinity], prm[CROSS.time_constant],
                         prm[CROSS.rate_exponent])
    G = prm[EOS.shear_modulus]
    if G > 0.0:  # elasto-viscoplastic: Maxwell relaxation at the viscous rate (Cross has no yield surface)
        gp = evp_cross_stress(s, L, eos_pressure(prm, rho), dt, G, mu0, mu_inf, A, m)
        mu = cross_viscosity(gp, mu0, mu_inf, A, m)
    else:
        mu = cross_viscosity(gdot, mu0, mu_inf, A, m)
        set_fluid_stress(s, L, eos_pressure(prm, rho), mu)
    state[0] = gdot
    state[1] = mu


class Cross(YieldFluid):
    name = "cross"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Generalized Cross shear-thinning fluid with Tait EOS pressure (source eq. 6)"
    Params = CrossParams
    state_vars = ("shear_rate", "effective_viscosity")
    layout = CROSS
    particle_stress = cross_stress

    @classmethod
    def pack(cls, p):
        return cls.pack_yield_fluid(p, viscosity_zero=p.viscosity_zero, viscosity_infinity=p.viscosity_infinity,
                            time_constant=p.time_constant, rate_exponent=p.rate_exponent)

    @classmethod
    def example_params(cls):
        return cls.Params(density=2650.0, sound_speed=30.0, from_bingham={"viscosity": 1.2, "yield_stress": 500.0})

    def largest_viscosity(self) -> float:
        return float(self.params.viscosity_zero)
