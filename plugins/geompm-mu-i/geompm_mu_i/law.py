"""mu(I) rheology of dense granular flow, elastoplastic form.

Jop, Forterre & Pouliquen (2006) Nature 441:727:

    |tau| = mu(I) p,   mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1),
    I = gamma_dot d / sqrt(p / rho_s)

p mean pressure (compression positive) [Pa], |tau| = sqrt(J2) of the
deviatoric stress, gamma_dot = sqrt(2 D':D') [1/s], d grain diameter [m],
rho_s grain density [kg/m3].

Integration (one step, Jaumann-objective): elastic predictor
sigma_tr = sigma_n + dt (W sigma - sigma W + lambda tr(D) I + 2 G D).  If
p_tr <= 0 the grains separate and the stress is zero (cohesionless).  Else the
deviator is capped at mu(I) p_tr with I from the current shear rate and p_tr.
The elastic branch regularises the law at small strain rates: as
gamma_dot -> 0, mu -> mu_s and the material responds as a Drucker-Prager-like
solid with friction mu_s, never as a viscosity that diverges (the failure
mode of the viscous form eta = mu(I) p / gamma_dot).  The elastic modulus is
a numerical stiffness: choose it so the elastic strains stay below ~1e-3.
"""

from __future__ import annotations

import math

from numba import njit
from pydantic import Field, model_validator

from geompm.materials.base import Material, MaterialParams
from geompm.materials.plausible import DENSITY, YOUNGS_MODULUS, Plausible
from geompm.materials.fluid import shear_rate
from geompm.contract.layout import param_layout
from geompm.materials.plasticity import (ELASTIC, current_moduli, kirchhoff_trial, elastic_wave_speed,
                                         set_scaled_deviator, sqrt_j2)

#: packed parameters: ELASTIC, mu_s, mu_2, I_0 [-], d [m], rho_s [kg/m3]
MU_I = param_layout(ELASTIC, "friction_static", "friction_limit", "inertial_number_ref", "grain_diameter",
                    "grain_density")


class MuIParams(MaterialParams):
    youngs_modulus: float = Field(gt=0, description="Young's modulus E of the grain skeleton [Pa]")
    poisson_ratio: float = Field(ge=0.0, lt=0.5, description="Poisson's ratio nu [-]")
    friction_static: float = Field(gt=0, description="mu_s: friction coefficient at I -> 0 [-] (0.38 glass beads)")
    friction_limit: float = Field(gt=0, description="mu_2: friction coefficient at I -> infinity [-] (0.64)")
    inertial_number_ref: float = Field(gt=0, description="I_0 [-] (0.279 for glass beads)")
    grain_diameter: float = Field(gt=0, description="d: grain diameter [m]")
    grain_density: float = Field(gt=0, description="rho_s: density of the grains [kg/m3]")

    @model_validator(mode="after")
    def _order(self):
        if self.friction_limit < self.friction_static:
            raise ValueError("friction_limit (mu_2) must be >= friction_static (mu_s)")
        if self.density > self.grain_density:
            raise ValueError("density (bulk) cannot exceed grain_density")
        return self


@njit(cache=True, inline="always")
def mu_of_i(inertial, mu_s, mu_2, i0):
    if inertial <= 0.0:
        return mu_s
    return mu_s + (mu_2 - mu_s) / (i0 / inertial + 1.0)


@njit(cache=True)
def mu_i_stress(prm, dt, L, rho, s, state):
    """One particle's mu(I) update (module docstring); s (6,) and state (2,) in place."""
    lam, G = current_moduli(prm, rho)  # Kirchhoff-stress elasticity: the step does not depend on the density
    tr = kirchhoff_trial(s, L, dt, lam, G)
    mean = (tr[0] + tr[1] + tr[2]) / 3.0
    if mean >= 0.0:  # no confinement: grains separate
        for i in range(6):
            s[i] = 0.0
        state[0] = 0.0
        return
    pres = -mean
    inertial = shear_rate(L) * prm[MU_I.grain_diameter] / math.sqrt(pres / prm[MU_I.grain_density])
    tau_max = mu_of_i(inertial, prm[MU_I.friction_static], prm[MU_I.friction_limit],
                      prm[MU_I.inertial_number_ref]) * pres
    tau = sqrt_j2(tr, mean)
    scale = 1.0
    if tau > tau_max:
        scale = tau_max / tau
        state[1] += (tau - tau_max) / (math.sqrt(3.0) * G)
    state[0] = inertial
    set_scaled_deviator(s, tr, mean, scale, mean)


#: a grain diameter above 0.1 m is a boulder: mu(I) is calibrated on sand and beads given in metres
GRAIN_DIAMETER = Plausible("grain_diameter", high=0.1,
                           hint=lambda v: f"above 0.1 m: was it given in mm? ({v:g} mm is {v / 1000:g} m)")
GRAIN_DENSITY = Plausible("grain_density", low=500.0,
                          hint=lambda v: f"below 500 kg/m3: was it given in t/m3? ({v:g} t/m3 is {v * 1000:g} kg/m3)")


class MuI(Material):
    name = "mu_i"
    plausible = (DENSITY, YOUNGS_MODULUS, GRAIN_DIAMETER, GRAIN_DENSITY)
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator, compiles for sm_90 (geompm's tests/cuda/cuda_parity.py, cuda_compile.py)
    description = "mu(I) granular rheology (Jop, Forterre & Pouliquen 2006), elastoplastic form"
    Params = MuIParams
    state_vars = ("inertial_number", "plastic_strain")
    layout = MU_I
    particle_stress = mu_i_stress
    particle_wave_speed = elastic_wave_speed

    @classmethod
    def pack(cls, p):
        E, nu = p.youngs_modulus, p.poisson_ratio
        return {"density": p.density, "lam": E * nu / ((1 + nu) * (1 - 2 * nu)), "G": E / (2 * (1 + nu)),
                "friction_static": p.friction_static, "friction_limit": p.friction_limit,
                "inertial_number_ref": p.inertial_number_ref, "grain_diameter": p.grain_diameter,
                "grain_density": p.grain_density}

    @classmethod
    def example_params(cls):
        """Glass beads of Jop et al. (2006): mu_s = tan 20.9 deg, mu_2 = tan 32.76 deg, I_0 = 0.279."""
        return cls.Params(density=1500.0, youngs_modulus=1.0e6, poisson_ratio=0.3, friction_static=0.382,
                          friction_limit=0.643, inertial_number_ref=0.279, grain_diameter=0.5e-3,
                          grain_density=2500.0)

    def k0(self) -> float:
        return 1.0 - math.sin(math.atan(self.params.friction_static))

    def stiffness(self) -> float:
        return float(self.params.youngs_modulus)
