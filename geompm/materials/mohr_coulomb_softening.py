"""Strain-softening Mohr-Coulomb soil: the Mohr-Coulomb law of mohr_coulomb.py whose cohesion, friction
angle and dilation angle fall from peak to residual with the equivalent plastic shear strain.

Each step takes c, phi and psi at the particle's plastic strain at the start of the step (softening.py:
the curve, linear or exponential, and its regularisation by the cell size), then returns the Kirchhoff
trial stress to that hexagon exactly as mohr_coulomb.mc_update does (de Souza Neto, Peric & Owen 2008,
sec. 8.2).  The dilatancy cut-off acts as in mohr_coulomb.py.  Softening laws: Soga et al. (2016,
Geotechnique 66(3):248), Yerro, Alonso & Pinyol (2016, Computers and Geotechnics 80:427).
"""

from __future__ import annotations

import math

from numba import njit

from geompm.contract.layout import param_layout
from geompm.materials.mohr_coulomb import MohrCoulomb, MohrCoulombParams, mc_update
from geompm.materials.plasticity import ELASTIC, current_moduli, kirchhoff_trial
from geompm.materials.softening import SOFT, SofteningFields, SofteningLaw, pack_softening, strength_at

#: packed parameters: ELASTIC, SOFT, the dilatancy cut-off eps_v^p [-] (inf: none)
MCS = param_layout(ELASTIC, SOFT, "dilation_cutoff")


class MohrCoulombSofteningParams(MohrCoulombParams, SofteningFields):
    """The law's parameters and the residual strength and softening curve (softening.SofteningFields)."""


@njit(cache=True)
def mc_softening_stress(prm, dt, L, rho, s, state):
    """One particle's softening MC return (module docstring); s (6,) and state (2,) in place."""
    lam, G = current_moduli(prm, rho)
    phi, psi, c = strength_at(prm, state[0])
    spsi = math.sin(psi) if state[1] < prm[MCS.dilation_cutoff] else 0.0
    tr = kirchhoff_trial(s, L, dt, lam, G)
    mc_update(s, state, tr, lam, G, math.sin(phi), math.cos(phi), spsi, c)


class MohrCoulombSoftening(SofteningLaw, MohrCoulomb):
    name = "mohr_coulomb_softening"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Mohr-Coulomb soil softening from peak to residual with plastic shear strain, regularised by the cell size"
    Params = MohrCoulombSofteningParams
    layout = MCS
    particle_stress = mc_softening_stress

    @classmethod
    def pack(cls, p):
        return {**cls.elastic_pack(p), **pack_softening(p), "dilation_cutoff": p.cutoff()}
