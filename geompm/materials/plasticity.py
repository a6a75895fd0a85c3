"""Shared pieces of the elastoplastic laws: elastic constants, elastic predictor,
the deviator scaling of a radial return, the elastic wave speed and a base class.

Laws that use ``elastic_wave_speed`` start their parameter layout from
``ELASTIC`` (density, lam, G).

The trial stress of a step is the Jaumann-rotated old stress plus the elastic
increment:  sigma_tr = sigma_n + dt (W sigma - sigma W) + dt (lambda tr(D) I + 2 G D).
"""

import math

from numba import njit
from pydantic import Field

from geompm.kernels.voigt import jaumann_increment
from geompm.materials.base import Material, MaterialParams
from geompm.materials.plausible import COHESION, DENSITY, YOUNGS_MODULUS, angle
from geompm.contract.layout import param_layout

#: the first slots of every law with an isotropic elastic part: rho0 [kg/m3], Lame lambda and G [Pa]
ELASTIC = param_layout("density", "lam", "G")


def lame_constants(E: float, nu: float) -> tuple[float, float]:
    """Lame's lambda and G [Pa] of Young's modulus E [Pa] and Poisson's ratio nu."""
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


class ElastoplasticParams(MaterialParams):
    youngs_modulus: float = Field(gt=0, description="Young's modulus E [Pa]")
    poisson_ratio: float = Field(ge=0.0, lt=0.5, description="Poisson's ratio nu [-], 0 <= nu < 0.5")
    friction_angle: float = Field(ge=0.0, lt=90.0, description="Friction angle phi [deg], 0 <= phi < 90")
    cohesion: float = Field(0.0, ge=0.0, description="Cohesion c [Pa]; 0 for granular soil")
    dilation_angle: float = Field(0.0, ge=0.0, lt=90.0, description="Dilation angle psi [deg], psi <= phi")
    dilation_cutoff: float | None = Field(
        None, gt=0.0, description="Dilatancy cut-off: the plastic volumetric strain eps_v^p [-] (dilatant positive) "
        "at which the soil reaches its loosest state and flows on at constant volume (psi = 0); "
        "ln((1 + e_max) / (1 + e_0)) for the void ratios e_0 (initial) and e_max.  Default: none, the "
        "soil dilates at psi for ever")

    def cutoff(self) -> float:
        """The dilatancy cut-off for the kernels: infinite when there is none."""
        return math.inf if self.dilation_cutoff is None else float(self.dilation_cutoff)

    def lame(self):
        return lame_constants(self.youngs_modulus, self.poisson_ratio)

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
def kirchhoff_trial(s, L, dt, lam, G):
    """The elastic predictor of the Kirchhoff rate (current_moduli: lam, G already at the current density):
    s / (1 + tr(D) dt) plus the Jaumann rotation and lam tr(D) dt I + 2 G D dt, so that J sigma advances
    by C : D dt (plus the rotation) with the volume ratio J_{n+1} / J_n = 1 + tr(D) dt.  That ratio is
    exactly 1 in isochoric shear and rigid rotation, where the engine's det(I + dt L) (kernels/volume.py)
    differs from it at second order in dt.  A Voigt 6-tuple."""
    tr = elastic_trial(s, L, dt, lam, G)
    v = (L[0, 0] + L[1, 1] + L[2, 2]) * dt
    shrink = -v / (1.0 + v)  # s_n (1 / (1 + v) - 1): J s_n is carried unchanged
    return (tr[0] + s[0] * shrink, tr[1] + s[1] * shrink, tr[2] + s[2] * shrink,
            tr[3] + s[3] * shrink, tr[4] + s[4] * shrink, tr[5] + s[5] * shrink)


@njit(cache=True, inline="always")
def moduli_predictor(prm, dt, L, rho, s):
    """The elastic predictor of a law with current_moduli and kirchhoff_trial (Material.elastic_predictor)."""
    lam, G = current_moduli(prm, rho)
    return kirchhoff_trial(s, L, dt, lam, G)


@njit(cache=True, inline="always")
def sqrt_j2(s, mean):
    d0 = s[0] - mean
    d1 = s[1] - mean
    d2 = s[2] - mean
    return math.sqrt(0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5])



@njit(cache=True, inline="always")
def set_scaled_deviator(s, tr, mean, scale, new_mean):
    """s <- scale * dev(tr) + new_mean I (Voigt, in place): the end of a radial return."""
    s[0] = (tr[0] - mean) * scale + new_mean
    s[1] = (tr[1] - mean) * scale + new_mean
    s[2] = (tr[2] - mean) * scale + new_mean
    s[3] = tr[3] * scale
    s[4] = tr[4] * scale
    s[5] = tr[5] * scale


@njit(cache=True, inline="always")
def current_moduli(prm, rho):
    """(lambda, G) [Pa] at the current density rho: the reference moduli times rho / rho0.

    The elastic laws integrate the Kirchhoff stress tau = J sigma (J = rho0 / rho) with constant moduli,
    tau_dot = lambda tr(D) I + 2 G D (Jaumann), so the Cauchy stress they store follows
    sigma_dot = (rho / rho0)(lambda tr(D) I + 2 G D) - sigma tr(D); the last term, of order sigma / E
    against the first, is left out.  A particle's internal force V sigma grad N = V0 tau grad N then does
    not grow with its dilation: a particle at rho0 / 10 is as stiff per unit mass as one at rho0, and the
    stable step does not depend on the density (elastic_wave_speed).  Simo & Hughes (1998) Computational
    Inelasticity, sec. 7.1 and 9.1 (Kirchhoff stress in finite-strain elastoplasticity); design decision 44."""
    r = rho / prm[ELASTIC.density]
    return prm[ELASTIC.lam] * r, prm[ELASTIC.G] * r


@njit(cache=True)
def elastic_wave_speed(prm, rho):
    """P-wave speed sqrt((lambda + 2G) / rho0) [m/s] of a law with current_moduli, at any density rho.

    Its moduli scale with rho / rho0 (current_moduli), so (lambda + 2G) rho / rho0 / rho does not depend
    on rho.  With constant moduli the speed would be sqrt((lambda + 2G) / rho): a particle dilated to
    rho0 / 25 (a stress-free particle on the floor of a column collapse at h = H0/80) would set a step five
    times shorter than the material's (docs/numerical-envelope.md)."""
    return math.sqrt((prm[ELASTIC.lam] + 2.0 * prm[ELASTIC.G]) / prm[ELASTIC.density])


def reduced_angles(phi_deg: float, psi_deg: float, factor: float) -> tuple[float, float]:
    """(phi_F, psi_F) [deg] of the strength-reduction method: tan(phi_F) = tan(phi) / F, and the dilation
    angle kept unless it exceeds phi_F, where it becomes phi_F, so an associated soil stays associated and a
    non-associated one keeps its psi (Brinkgreve & Bakker 1991, Proc. 7th IACMAG, 1117-1122: the phi-c
    reduction of PLAXIS).  Griffiths & Lane (1999, Geotechnique 49(3):387) reduce c and tan(phi) alike."""
    phi = math.degrees(math.atan(math.tan(math.radians(phi_deg)) / factor))
    return phi, min(psi_deg, phi)


class FrictionalMaterial(Material):
    """Base of the Mohr-Coulomb-type soil laws (ElastoplasticParams)."""

    plausible = (DENSITY, YOUNGS_MODULUS, angle("friction_angle"), COHESION)
    strength_reduction = True

    particle_wave_speed = elastic_wave_speed
    elastic_predictor = moduli_predictor

    @classmethod
    def strength_reduced(cls, params, factor: float) -> dict:
        """c / F, tan(phi) / F, and psi kept unless it exceeds the reduced phi (reduced_angles)."""
        phi, psi = reduced_angles(params.friction_angle, params.dilation_angle, factor)
        return {"cohesion": params.cohesion / factor, "friction_angle": phi, "dilation_angle": psi}

    @staticmethod
    def elastic_pack(p) -> dict:
        """The ELASTIC slots of a law with youngs_modulus and poisson_ratio."""
        lam, G = lame_constants(p.youngs_modulus, p.poisson_ratio)
        return {"density": p.density, "lam": lam, "G": G}

    def k0(self) -> float:
        """Jaky (1944): K0 = 1 - sin(phi)."""
        return 1.0 - math.sin(math.radians(self.params.friction_angle))

    def stiffness(self) -> float:
        return float(self.params.youngs_modulus)

    def warnings(self) -> list[str]:
        p = self.params
        if p.dilation_angle > 0.0 and p.dilation_cutoff is None:
            return [f"dilation_angle = {p.dilation_angle:g} deg with no dilation_cutoff: under continued shear the "
                    "soil dilates without bound, its density falls (to 4 % of rho0 in the column collapse at "
                    "psi = 10 deg, h = 5 mm) and the stable time step with it, as sqrt(rho / rho0). Set "
                    "dilation_cutoff to the plastic volumetric strain of the loosest state, "
                    "ln((1 + e_max) / (1 + e_0)), e.g. 0.05 (docs/numerical-envelope.md, Dilatancy)"]
        return []
