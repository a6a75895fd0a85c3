"""Strain softening shared by the softening Mohr-Coulomb and Drucker-Prager laws: the curve and its
regularisation by the cell size.

Cohesion c, friction angle phi and dilation angle psi each fall from their peak to their residual value
as the equivalent plastic shear strain eps_p (state variable ``plastic_strain``, sqrt(2/3 e_p : e_p) of
the deviatoric plastic strain) grows past ``start`` (eps_1):

    linear:       x = x_p + (x_r - x_p) (eps_p - eps_1) / (eps_2 - eps_1),   eps_1 <= eps_p <= eps_2
    exponential:  x = x_r + (x_p - x_r) exp(-ln(100) (eps_p - eps_1) / (eps_2 - eps_1)),   eps_p >= eps_1

(x = x_p before eps_1; linear: x = x_r after eps_2; exponential: 1 % of the drop remains at eps_2).  The
angles are interpolated in degrees.  The strength of the step comes from eps_p at its start (an explicit
update; a step's plastic strain increment is a small fraction of eps_2 - eps_1 at the Courant numbers of
an explicit MPM run).  Yerro, Alonso & Pinyol (2016, Computers and Geotechnics 80:427) use the exponential
form; Soga et al. (2016, Geotechnique 66(3):248) the linear one.

Regularisation.  Softening localises into a shear band about one cell wide, so with thresholds fixed in
strain the band's displacement at residual, (eps_2 - eps_1) x h, and the energy the band dissipates per
unit area fall with the cell size h, and a refined grid fails more brittlely.  With
``reference_cell_size`` h_ref the thresholds given are those of a band h_ref wide and scale with the cell:

    eps_1(h) = eps_1 h_ref / h,      eps_2(h) = eps_2 h_ref / h,

so that the band's displacements eps_1 h_ref and eps_2 h_ref at the start and the end of softening, and
with them the energy dissipated per unit area of band, are material constants (the crack-band argument of
Bazant & Oh 1983, Materiaux et Constructions 16:155, carried to shear bands in softening soil by
Pietruszczak & Mroz 1981, Int. J. Numer. Meth. Eng. 17:327).  Without it the thresholds are strains, as
given, at every cell size.
"""

from __future__ import annotations

import math
from typing import Literal

from numba import njit
from pydantic import BaseModel, Field, model_validator

from geompm.contract.layout import param_layout
from geompm.materials.plasticity import ELASTIC, reduced_angles

LN100 = math.log(100.0)

#: packed softening parameters: peak and residual phi and psi [rad] and c [Pa], the thresholds eps_1 and
#: eps_2 at this cell size [-], 1.0 for the exponential curve (0.0 linear)
SOFT = param_layout("phi_peak", "phi_residual", "psi_peak", "psi_residual", "c_peak", "c_residual",
                    "soft_start", "soft_end", "soft_exponential")
#: where SOFT starts in a softening law's layout: right after ELASTIC, param_layout(ELASTIC, SOFT, ...)
SOFT_BASE = len(ELASTIC._fields)


class SofteningSpec(BaseModel):
    model_config = {"extra": "forbid", "allow_inf_nan": False}
    start: float = Field(ge=0.0, description="Equivalent plastic shear strain eps_1 [-] at which softening starts")
    end: float = Field(gt=0.0, description="Equivalent plastic shear strain eps_2 [-] at which the residual "
                                           "strength is reached (linear; exponential: 1 % of the drop left)")
    shape: Literal["linear", "exponential"] = Field("linear", description="How strength falls between them")
    reference_cell_size: float | None = Field(
        None, gt=0.0, description="h_ref [m]: the thresholds are those of a shear band h_ref wide and scale as "
        "h_ref / h with the cell size h, so the band's displacement at residual is a material constant "
        "(docs/slope-stability.md); default none: the thresholds are strains at every cell size")

    @model_validator(mode="after")
    def _order(self):
        if self.end <= self.start:
            raise ValueError(f"softening.end ({self.end:g}) must be above softening.start ({self.start:g}): the "
                             "residual strength is reached after softening starts")
        return self


class SofteningFields(BaseModel):
    """The residual strength and the softening curve of a softening law's parameters."""

    residual_cohesion: float = Field(ge=0.0, description="Residual cohesion c_r [Pa], at most the peak cohesion")
    residual_friction_angle: float = Field(ge=0.0, lt=90.0, description="Residual friction angle phi_r [deg], at "
                                                                        "most the peak friction angle")
    residual_dilation_angle: float = Field(0.0, ge=0.0, lt=90.0, description="Residual dilation angle psi_r [deg]")
    softening: SofteningSpec = Field(description="Where and how the strength falls from peak to residual")

    @model_validator(mode="after")
    def _residual(self):
        problems = [f"{r} ({getattr(self, r):g}) must not exceed the peak {p} ({getattr(self, p):g})"
                    for r, p in (("residual_cohesion", "cohesion"), ("residual_friction_angle", "friction_angle"),
                                 ("residual_dilation_angle", "dilation_angle"))
                    if getattr(self, r) > getattr(self, p)]
        if self.residual_dilation_angle > self.residual_friction_angle:
            problems.append("residual_dilation_angle must not exceed residual_friction_angle")
        if problems:
            raise ValueError("; ".join(problems))
        return self


class SofteningLaw:
    """What the softening laws share beside their kernel: the thresholds at the cell size, the strength
    reduction of peak and residual, and the conformance suite's example (a mixin before the law's base)."""

    @classmethod
    def at_cell_size(cls, params, cell_size: float):
        """``params`` with the softening thresholds of a band ``cell_size`` wide (module docstring)."""
        sp = params.softening
        if sp.reference_cell_size is None:
            return params
        r = sp.reference_cell_size / cell_size
        return params.model_copy(update={"softening": sp.model_copy(update={"start": sp.start * r,
                                                                             "end": sp.end * r})})

    @classmethod
    def strength_reduced(cls, params, factor: float) -> dict:
        return reduce_softening(params, factor)

    @classmethod
    def example_params(cls):
        return cls.Params(density=2650.0, youngs_modulus=0.84e6, poisson_ratio=0.3, friction_angle=31.0,
                          cohesion=100.0, dilation_angle=5.0, residual_cohesion=0.0, residual_friction_angle=22.0,
                          softening={"start": 0.0, "end": 0.05})


def pack_softening(p) -> dict:
    """The SOFT slots of softening params ``p`` (thresholds as they stand: at_cell_size has been applied)."""
    sp = p.softening
    return {"phi_peak": math.radians(p.friction_angle), "phi_residual": math.radians(p.residual_friction_angle),
            "psi_peak": math.radians(p.dilation_angle), "psi_residual": math.radians(p.residual_dilation_angle),
            "c_peak": p.cohesion, "c_residual": p.residual_cohesion, "soft_start": sp.start, "soft_end": sp.end,
            "soft_exponential": 1.0 if sp.shape == "exponential" else 0.0}


def reduce_softening(p, factor: float) -> dict:
    """Peak and residual strength divided by F alike (plasticity.reduced_angles for each pair)."""
    phi, psi = reduced_angles(p.friction_angle, p.dilation_angle, factor)
    phi_r, psi_r = reduced_angles(p.residual_friction_angle, p.residual_dilation_angle, factor)
    return {"cohesion": p.cohesion / factor, "friction_angle": phi, "dilation_angle": psi,
            "residual_cohesion": p.residual_cohesion / factor, "residual_friction_angle": phi_r,
            "residual_dilation_angle": psi_r}


@njit(cache=True, inline="always")
def softened(peak, residual, eps, start, end, exponential):
    """The value at equivalent plastic shear strain eps on the softening curve (module docstring)."""
    if eps <= start:
        return peak
    if exponential > 0.5:
        return residual + (peak - residual) * math.exp(-LN100 * (eps - start) / (end - start))
    if eps >= end:
        return residual
    return peak + (residual - peak) * (eps - start) / (end - start)


@njit(cache=True, inline="always")
def strength_at(prm, eps):
    """(phi, psi [rad], c [Pa]) at plastic strain eps, from the SOFT slots of a layout that starts
    ELASTIC, SOFT (SOFT_BASE)."""
    base = SOFT_BASE
    a, b, x = prm[base + SOFT.soft_start], prm[base + SOFT.soft_end], prm[base + SOFT.soft_exponential]
    return (softened(prm[base + SOFT.phi_peak], prm[base + SOFT.phi_residual], eps, a, b, x),
            softened(prm[base + SOFT.psi_peak], prm[base + SOFT.psi_residual], eps, a, b, x),
            softened(prm[base + SOFT.c_peak], prm[base + SOFT.c_residual], eps, a, b, x))
