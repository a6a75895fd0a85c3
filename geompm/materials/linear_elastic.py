"""Linear elastic solid in rate form with the Jaumann (objective) stress rate.

    sigma_dot = (rho / rho0) (lambda tr(D) I + 2 G D) + W sigma - sigma W

D = sym(L) rate of deformation, W = skew(L) spin [1/s]; the factor rho / rho0
makes it the Cauchy rate of the Kirchhoff stress tau = J sigma under Hooke's
law (plasticity.current_moduli: a term sigma tr(D), of order sigma / E, left out);
G = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)).
Small-strain Hooke's law made objective for large rotations; see Belytschko,
Liu & Moran (2000) Nonlinear Finite Elements for Continua and Structures, sec. 5.7.
P-wave speed c_p = sqrt((lambda + 2 G) / rho0), at any density, bounds the time step.
"""

from __future__ import annotations

from numba import njit
from pydantic import Field

from geompm.materials.base import Material, MaterialParams
from geompm.materials.plausible import DENSITY, YOUNGS_MODULUS
from geompm.materials.plasticity import ELASTIC, current_moduli, kirchhoff_trial, elastic_wave_speed


class LinearElasticParams(MaterialParams):
    youngs_modulus: float = Field(gt=0, description="Young's modulus E [Pa]")
    poisson_ratio: float = Field(gt=-1.0, lt=0.5, description="Poisson's ratio nu [-], -1 < nu < 0.5")


@njit(fastmath=True, cache=True)
def elastic_stress(prm, dt, L, rho, s, state):
    """One particle's Jaumann-rate Hooke update; s (6,) in place."""
    lam, G = current_moduli(prm, rho)
    tr = kirchhoff_trial(s, L, dt, lam, G)
    for i in range(6):
        s[i] = tr[i]


class LinearElastic(Material):
    name = "linear_elastic"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Isotropic linear elasticity (Hooke) in rate form with the Jaumann stress rate"
    Params = LinearElasticParams
    plausible = (DENSITY, YOUNGS_MODULUS)
    layout = ELASTIC
    particle_stress = elastic_stress
    particle_wave_speed = elastic_wave_speed

    @classmethod
    def pack(cls, params):
        E, nu = params.youngs_modulus, params.poisson_ratio
        return {"density": params.density, "lam": E * nu / ((1 + nu) * (1 - 2 * nu)), "G": E / (2 * (1 + nu))}

    @classmethod
    def example_params(cls):
        return cls.Params(density=2000.0, youngs_modulus=1.0e7, poisson_ratio=0.3)

    def k0(self) -> float:
        nu = self.params.poisson_ratio
        return nu / (1.0 - nu)

    def stiffness(self) -> float:
        return float(self.params.youngs_modulus)
