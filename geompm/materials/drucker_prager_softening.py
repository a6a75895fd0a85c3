"""Strain-softening Drucker-Prager soil: the Drucker-Prager law of drucker_prager.py whose cohesion,
friction angle and dilation angle fall from peak to residual with the equivalent plastic shear strain.

Each step takes c, phi and psi at the particle's plastic strain at the start of the step (softening.py),
matches the cone to them (drucker_prager.dp_cone, the law's ``cone`` setting; past the dilatancy cut-off
the isochoric cone) and returns the Kirchhoff trial stress to it as drucker_prager.dp_return does (de Souza
Neto, Peric & Owen 2008, sec. 8.3.3).  The tension cut-off is the given one or the current apex, the lower.
"""

from __future__ import annotations

import math

from numba import njit

from geompm.contract.layout import param_layout
from geompm.materials.drucker_prager import CONES, DruckerPrager, DruckerPragerParams, dp_cone, dp_return
from geompm.materials.plasticity import ELASTIC, current_moduli, kirchhoff_trial
from geompm.materials.softening import SOFT, SofteningFields, SofteningLaw, pack_softening, strength_at

#: packed parameters: ELASTIC, SOFT, the cone's index in drucker_prager.CONES, the given tension cut-off [Pa]
#: (inf: the apex), the dilatancy cut-off eps_v^p [-] (inf: none)
DPS = param_layout(ELASTIC, SOFT, "cone", "tension_cutoff", "dilation_cutoff")


class DruckerPragerSofteningParams(DruckerPragerParams, SofteningFields):
    """The law's parameters and the residual strength and softening curve (softening.SofteningFields)."""


@njit(cache=True)
def dp_softening_stress(prm, dt, L, rho, s, state):
    """One particle's softening DP return (module docstring); s (6,) and state (2,) in place."""
    lam, G = current_moduli(prm, rho)
    phi, psi, c = strength_at(prm, state[0])
    if state[1] >= prm[DPS.dilation_cutoff]:
        psi = 0.0
    alpha, kc, beta = dp_cone(math.sin(phi), math.cos(phi), math.sin(psi), int(prm[DPS.cone]))
    k = kc * c
    tcut = prm[DPS.tension_cutoff]
    if alpha > 0.0:
        tcut = min(tcut, k / (3.0 * alpha))
    tr = kirchhoff_trial(s, L, dt, lam, G)
    dp_return(s, state, tr, lam + 2.0 * G / 3.0, G, alpha, k, beta, tcut)


class DruckerPragerSoftening(SofteningLaw, DruckerPrager):
    name = "drucker_prager_softening"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Drucker-Prager soil softening from peak to residual with plastic shear strain, regularised by the cell size"
    Params = DruckerPragerSofteningParams
    layout = DPS
    particle_stress = dp_softening_stress

    @classmethod
    def pack(cls, p):
        return {**cls.elastic_pack(p), **pack_softening(p), "cone": float(CONES.index(p.cone)),
                "tension_cutoff": math.inf if p.tension_cutoff is None else p.tension_cutoff,
                "dilation_cutoff": p.cutoff()}
