"""Shared pieces of the non-Newtonian fluid laws (Bingham, Cross).

Strain-rate tensor as in the source study: epsdot_ij = dv_i/dx_j + dv_j/dx_i
= 2 D_ij, and the shear rate gamma_dot = sqrt(0.5 epsdot_ij epsdot_ij)
= sqrt(2 D:D), which equals dv_x/dy in simple shear.  Deviatoric stress
tau = mu_eff epsdot' (eq. 3 of the source, on the deviatoric rate so the
weakly compressible fluid's volume change enters only through P), total
stress sigma = -P I + tau (eq. 4), P from the Tait EOS (eq. 5, tait.py).
"""

import math

from numba import njit


@njit(cache=True, inline="always")
def shear_rate(L):
    """gamma_dot = sqrt(2 D':D') of the deviatoric rate of deformation [1/s]."""
    tr3 = (L[0, 0] + L[1, 1] + L[2, 2]) / 3.0
    d0 = L[0, 0] - tr3
    d1 = L[1, 1] - tr3
    d2 = L[2, 2] - tr3
    d3 = 0.5 * (L[0, 1] + L[1, 0])
    d4 = 0.5 * (L[1, 2] + L[2, 1])
    d5 = 0.5 * (L[0, 2] + L[2, 0])
    return math.sqrt(2.0 * (d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * (d3 * d3 + d4 * d4 + d5 * d5)))


@njit(cache=True, inline="always")
def set_fluid_stress(s, L, P, mu):
    """s <- -P I + 2 mu D' (Voigt, in place)."""
    tr3 = (L[0, 0] + L[1, 1] + L[2, 2]) / 3.0
    s[0] = -P + 2.0 * mu * (L[0, 0] - tr3)
    s[1] = -P + 2.0 * mu * (L[1, 1] - tr3)
    s[2] = -P + 2.0 * mu * (L[2, 2] - tr3)
    s[3] = mu * (L[0, 1] + L[1, 0])
    s[4] = mu * (L[1, 2] + L[2, 1])
    s[5] = mu * (L[0, 2] + L[2, 0])
