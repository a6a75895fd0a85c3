"""Critical-state sand: friction and dilatancy that follow the solid volume fraction (Roux-Radjai dilatancy).

A granular soil denser than its critical state dilates when sheared and is stronger; one looser contracts and
is weaker; both reach the critical state (constant volume, critical stress ratio) under continued shear.  With
phi_s the solid volume fraction (1 - porosity), phi_c its critical value, K the dilatancy coefficient and
phi_cs the critical-state friction angle (Roux & Radjai 1998, in Physics of Dry Granular Media, NATO ASI 350,
pp. 229-236; Pailha & Pouliquen 2009, J. Fluid Mech. 633:115, eq. 2.5-2.6; Rondon, Pouliquen & Aussillous
2011, Phys. Fluids 23:073301, eq. 3-4):

    tan psi   = K (phi_s - phi_c)                         dilatancy angle psi (negative: contraction)
    tan phi_m = tan phi_cs + tan psi                      mobilised friction (Taylor's stress-dilatancy)

The solid fraction comes from the particle's current density: phi_s = rho / rho_g with the grain density
rho_g = rho_0 / phi_s0 (rho_0 the law's reference density: the dry density of a dry soil, the skeleton's
(1 - n0) rho_s of a saturated one, so rho / rho_g = 1 - n in both).  The soil's own volume change therefore
moves it towards the critical state: contraction raises phi_s, dilation lowers it, and at phi_s = phi_c the
flow is isochoric at tan phi_cs.

Each step matches the plane-strain Drucker-Prager cone to (phi_m, psi) at the start of the step
(drucker_prager.dp_cone) and returns the Kirchhoff trial stress to it (drucker_prager.dp_return; de Souza Neto,
Peric & Owen 2008, sec. 8.3.3), with the cohesion c (default 0: the apex at zero mean stress; the tension
cut-off at the apex).  A contracting flow (psi < 0) has a
negative potential slope beta; beta is bounded so that the return's modulus G + 9 K_b alpha beta stays above
G / 4 (K_b the bulk modulus), a bound that acts only below psi of about -30 degrees.  The mobilised friction is
bounded below by zero (a separated, very loose particle has no strength).

State variables: the equivalent plastic shear strain and plastic volumetric strain of drucker_prager.py, and the
solid fraction phi_s at the step (for output).  Rate-independent: the rate dependence of phi_c and of the friction
(the viscous number of Boyer, Guazzelli & Pouliquen 2011) is not modelled here.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from pydantic import Field, model_validator

from geompm.contract.layout import param_layout
from geompm.materials.base import MaterialParams
from geompm.materials.drucker_prager import dp_cone, dp_return
from geompm.materials.plasticity import ELASTIC, FrictionalMaterial, current_moduli, kirchhoff_trial
from geompm.materials.plausible import COHESION, DENSITY, YOUNGS_MODULUS, Plausible, angle

#: packed parameters: ELASTIC, tan of the critical friction angle [-], the critical solid fraction [-], the
#: dilatancy coefficient K [-], the grain density rho_0 / phi_s0 [kg/m3], the cohesion c [Pa]
CSS = param_layout(ELASTIC, "tan_phi_cs", "phi_c", "dilatancy", "rho_grain", "cohesion")

#: the densest packing of equal spheres (Kepler's, proven by Hales 2005): no granular soil is denser
DENSEST_PACKING = 0.7405


class CriticalStateSandParams(MaterialParams):
    youngs_modulus: float = Field(gt=0, description="Young's modulus E of the skeleton [Pa]")
    poisson_ratio: float = Field(ge=0.0, lt=0.5, description="Poisson's ratio nu [-], 0 <= nu < 0.5")
    critical_friction_angle: float = Field(
        gt=0.0, lt=90.0, description="Friction angle at the critical state phi_cs [deg] (constant-volume shear)")
    critical_solid_fraction: float = Field(
        gt=0.0, lt=DENSEST_PACKING, description="Solid volume fraction at the critical state phi_c [-] "
        "(1 - the critical porosity); denser soil dilates, looser contracts")
    dilatancy_coefficient: float = Field(
        gt=0.0, description="K [-] in tan(psi) = K (phi_s - phi_c): the dilatancy angle per unit of solid fraction "
        "away from critical (Pailha & Pouliquen 2009 fit K = 4.09 to glass beads)")
    solid_fraction: float | None = Field(
        None, gt=0.0, lt=1.0, description="Initial solid volume fraction phi_s0 [-] (1 - porosity). A saturated "
        "material takes it from pore_water.porosity (give it there); required for a dry one")
    cohesion: float = Field(
        0.0, ge=0.0, description="Cohesion c [Pa] of the matched cone, with the friction phi_m: an apparent "
        "cohesion (the suction of an unsaturated sand, roots, fines); 0 for a clean sand")
    max_solid_fraction: float = Field(
        DENSEST_PACKING, gt=0.0, le=DENSEST_PACKING,
        description="The densest state the soil can reach [-] (e.g. 1 - n_min of the sand); a denser initial "
        "state is refused. Default 0.7405, the densest packing of equal spheres")

    @model_validator(mode="after")
    def _range(self):
        if self.max_solid_fraction <= self.critical_solid_fraction:
            raise ValueError(f"max_solid_fraction {self.max_solid_fraction:g} must exceed critical_solid_fraction "
                             f"{self.critical_solid_fraction:g}")
        return self

    def loosest(self) -> float:
        """The solid fraction below which the mobilised friction vanishes: phi_c - tan(phi_cs) / K."""
        return self.critical_solid_fraction - math.tan(math.radians(self.critical_friction_angle)) / \
            self.dilatancy_coefficient

    def with_porosity(self, porosity: float):
        update = super().with_porosity(porosity)
        return update.model_copy(update={"solid_fraction": 1.0 - porosity})

    def saturation_checks(self, porosity: float | None) -> tuple[list, list]:
        if porosity is None and self.solid_fraction is None:
            return [("solid_fraction", "a dry critical-state sand needs its initial solid volume fraction "
                                       "(1 - porosity), e.g. 0.6; give solid_fraction")], []
        warnings = []
        if porosity is not None and self.solid_fraction is not None and abs(self.solid_fraction + porosity - 1) > 1e-9:
            warnings.append(("solid_fraction", f"{self.solid_fraction:g} is replaced by 1 - pore_water.porosity = "
                             f"{1 - porosity:g}: the pore water's porosity sets a saturated soil's solid fraction; "
                             "remove solid_fraction"))
        phi0 = 1.0 - porosity if porosity is not None else self.solid_fraction
        where = "pore_water.porosity" if porosity is not None else "solid_fraction"
        if phi0 > self.max_solid_fraction:
            return [(where, f"a solid fraction {phi0:g} is denser than max_solid_fraction {self.max_solid_fraction:g}"
                            " (the densest state the soil can reach): lower it, or raise max_solid_fraction")], warnings
        if phi0 <= self.loosest():
            return [(where, f"a solid fraction {phi0:g} is looser than the loosest state the parameters allow, "
                            f"phi_c - tan(phi_cs) / K = {self.loosest():.4g}, where the mobilised friction vanishes: "
                            "the soil would have no strength; raise it or lower dilatancy_coefficient")], warnings
        return [], warnings


@njit(cache=True, inline="always")
def mobilised(prm, phi_s):
    """(tan phi_m, tan psi) at the solid fraction phi_s (module docstring), the friction never negative."""
    tan_psi = max(prm[CSS.dilatancy] * (phi_s - prm[CSS.phi_c]), -prm[CSS.tan_phi_cs])
    return prm[CSS.tan_phi_cs] + tan_psi, tan_psi


@njit(cache=True)
def css_stress(prm, dt, L, rho, s, state):
    """One particle's critical-state sand return (module docstring); s (6,) and state (3,) in place."""
    lam, G = current_moduli(prm, rho)
    K = lam + 2.0 * G / 3.0
    phi_s = rho / prm[CSS.rho_grain]
    tan_phi, tan_psi = mobilised(prm, phi_s)
    cos_phi = 1.0 / math.sqrt(1.0 + tan_phi * tan_phi)
    sin_psi = tan_psi / math.sqrt(1.0 + tan_psi * tan_psi)
    alpha, kc, beta = dp_cone(tan_phi * cos_phi, cos_phi, sin_psi, 0)
    beta = max(beta, -0.75 * G / (9.0 * K * alpha)) if alpha > 0.0 else beta
    k = kc * prm[CSS.cohesion]
    tr = kirchhoff_trial(s, L, dt, lam, G)
    dp_return(s, state, tr, K, G, alpha, k, beta, k / (3.0 * alpha) if alpha > 0.0 else 0.0)
    state[2] = phi_s


class CriticalStateSand(FrictionalMaterial):
    name = "critical_state_sand"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Critical-state sand: friction and dilatancy from the solid fraction (Roux-Radjai), with an optional cohesion"
    Params = CriticalStateSandParams
    state_vars = ("plastic_strain", "plastic_volumetric_strain", "solid_fraction")
    layout = CSS
    particle_stress = css_stress
    strength_reduction = False
    plausible = (DENSITY, YOUNGS_MODULUS, angle("critical_friction_angle"), COHESION,
                 Plausible("dilatancy_coefficient", high=20.0, hint=lambda v: (
                     f"above 20: a 0.01 change of solid fraction would turn the dilatancy angle by more than "
                     f"{math.degrees(math.atan(0.01 * v)):.2g} deg; sands and glass beads measure 1-10")))

    @classmethod
    def pack(cls, p):
        if p.solid_fraction is None:
            raise ValueError("critical_state_sand: solid_fraction is unset (the case check names it)")
        return {**cls.elastic_pack(p), "tan_phi_cs": math.tan(math.radians(p.critical_friction_angle)),
                "phi_c": p.critical_solid_fraction, "dilatancy": p.dilatancy_coefficient,
                "rho_grain": p.density / p.solid_fraction, "cohesion": p.cohesion}

    @classmethod
    def example_params(cls):
        return cls.Params(density=1500.0, youngs_modulus=1.0e7, poisson_ratio=0.3, critical_friction_angle=30.0,
                          critical_solid_fraction=0.58, dilatancy_coefficient=4.09, solid_fraction=0.55)

    def friction_and_dilatancy(self, phi_s: float) -> tuple[float, float]:
        """(phi_m, psi) [deg] at the solid fraction ``phi_s`` (module docstring)."""
        tan_phi, tan_psi = mobilised(self.prm, phi_s)
        return math.degrees(math.atan(tan_phi)), math.degrees(math.atan(tan_psi))

    def k0(self) -> float:
        """Jaky (1944), K0 = 1 - sin(phi_m), with the friction mobilised at the initial solid fraction."""
        return 1.0 - math.sin(math.radians(self.friction_and_dilatancy(self.params.solid_fraction)[0]))

    def initial_state(self, n: int) -> np.ndarray:
        out = np.zeros((n, len(self.state_vars)))
        out[:, 2] = self.params.solid_fraction
        return out

    def warnings(self) -> list[str]:
        phi, psi = self.friction_and_dilatancy(self.params.solid_fraction)
        if abs(psi) > 25.0:
            return [f"the initial solid fraction {self.params.solid_fraction:g} gives a dilatancy angle of "
                    f"{psi:.3g} deg (mobilised friction {phi:.3g} deg): beyond the 0-25 deg that sands show; check "
                    "dilatancy_coefficient and critical_solid_fraction"]
        return []
