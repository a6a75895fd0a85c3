"""Shared pieces of the elastoplastic laws: elastic constants, elastic predictor,
the deviator scaling of a radial return, the elastic wave speed and a base class.

Kernels that use ``elastic_wave_speed`` pack their parameters as
[density, lambda, G, ...].

The trial stress of a step is the Jaumann-rotated old stress plus the elastic
increment:  sigma_tr = sigma_n + dt (W sigma - sigma W) + dt (lambda tr(D) I + 2 G D).
"""

import math

import numpy as np
from numba import njit
from pydantic import Field

from ..kernels.voigt import jaumann_increment
from .base import Material, MaterialParams


class ElastoplasticParams(MaterialParams):
    youngs_modulus: float = Field(gt=0, description="Young's modulus E [Pa]")
    poisson_ratio: float = Field(ge=0.0, lt=0.5, description="Poisson's ratio nu [-], 0 <= nu < 0.5")
    friction_angle: float = Field(ge=0.0, lt=90.0, description="Friction angle phi [deg], 0 <= phi < 90")
    cohesion: float = Field(0.0, ge=0.0, description="Cohesion c [Pa]; 0 for granular soil")
    dilation_angle: float = Field(0.0, ge=0.0, lt=90.0, description="Dilation angle psi [deg], psi <= phi")

    def lame(self):
        E, nu = self.youngs_modulus, self.poisson_ratio
        return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))

    def check_dilation(self):
        if self.dilation_angle > self.friction_angle:
            raise ValueError("dilation_angle must not exceed friction_angle")
        return self


@njit(cache=True, inline="always")
def elastic_trial(s, L, dt, lam, G):
    """Jaumann-rotated s plus the elastic increment, as a Voigt 6-tuple."""
    jz = jaumann_increment(s, L, dt)
    tr = (L[0, 0] + L[1, 1] + L[2, 2]) * dt
    return (
        s[0] + jz[0] + lam * tr + 2.0 * G * L[0, 0] * dt,
        s[1] + jz[1] + lam * tr + 2.0 * G * L[1, 1] * dt,
        s[2] + jz[2] + lam * tr + 2.0 * G * L[2, 2] * dt,
        s[3] + jz[3] + G * (L[0, 1] + L[1, 0]) * dt,
        s[4] + jz[4] + G * (L[1, 2] + L[2, 1]) * dt,
        s[5] + jz[5] + G * (L[0, 2] + L[2, 0]) * dt,
    )


@njit(cache=True, inline="always")
def sqrt_j2(s, mean):
    d0 = s[0] - mean
    d1 = s[1] - mean
    d2 = s[2] - mean
    return np.sqrt(0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5])



@njit(cache=True, inline="always")
def set_scaled_deviator(s, tr, mean, scale, new_mean):
    """s <- scale * dev(tr) + new_mean I (Voigt, in place): the end of a radial return."""
    s[0] = (tr[0] - mean) * scale + new_mean
    s[1] = (tr[1] - mean) * scale + new_mean
    s[2] = (tr[2] - mean) * scale + new_mean
    s[3] = tr[3] * scale
    s[4] = tr[4] * scale
    s[5] = tr[5] * scale


@njit(cache=True)
def elastic_wave_speed(prm, p_rho):
    """P-wave speed sqrt((lambda + 2G) / rho0) [m/s] for prm = [rho0, lambda, G, ...]."""
    return math.sqrt((prm[1] + 2.0 * prm[2]) / prm[0])


class FrictionalMaterial(Material):
    """Base of the Mohr-Coulomb-type soil laws (ElastoplasticParams)."""

    wave_speed_kernel = elastic_wave_speed

    def k0(self) -> float:
        """Jaky (1944): K0 = 1 - sin(phi)."""
        return 1.0 - math.sin(math.radians(self.params.friction_angle))

    def stiffness(self) -> float:
        return float(self.params.youngs_modulus)
