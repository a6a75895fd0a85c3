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

from geompm.kernels.voigt import jaumann_increment


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


@njit(cache=True, inline="always")
def evp_trial(s, L, dt, G):
    """The elastic trial deviator tau_n^J + 2 G D' dt as a Voigt 6-tuple (tau_n^J the Jaumann-rotated
    deviator of s)."""
    jz = jaumann_increment(s, L, dt)
    r0, r1, r2 = s[0] + jz[0], s[1] + jz[1], s[2] + jz[2]
    m = (r0 + r1 + r2) / 3.0
    tr3 = (L[0, 0] + L[1, 1] + L[2, 2]) / 3.0
    g2 = 2.0 * G * dt
    return (r0 - m + g2 * (L[0, 0] - tr3), r1 - m + g2 * (L[1, 1] - tr3), r2 - m + g2 * (L[2, 2] - tr3),
            s[3] + jz[3] + G * dt * (L[0, 1] + L[1, 0]), s[4] + jz[4] + G * dt * (L[1, 2] + L[2, 1]),
            s[5] + jz[5] + G * dt * (L[0, 2] + L[2, 0]))


@njit(cache=True, inline="always")
def set_scaled_trial(s, t, scale, P):
    """s <- -P I + scale * t (Voigt, in place), t a deviator 6-tuple."""
    s[0] = scale * t[0] - P
    s[1] = scale * t[1] - P
    s[2] = scale * t[2] - P
    s[3] = scale * t[3]
    s[4] = scale * t[4]
    s[5] = scale * t[5]


@njit(cache=True, inline="always")
def equivalent_shear(t):
    """sqrt(t : t / 2) of a deviator 6-tuple t (= |t_xy| in simple shear) [Pa]."""
    return math.sqrt(0.5 * (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) + t[3] * t[3] + t[4] * t[4] + t[5] * t[5])


@njit(cache=True, inline="always")
def evp_yield_stress(s, L, P, dt, G, tau_y, K, n):
    """Elasto-viscoplastic update with a yield surface, for Bingham (n = 1) and Herschel-Bulkley fluids:
    s <- -P I + tau_{n+1} (Voigt, in place).

    Trial deviator tau_tr = tau_n^J + 2 G D' dt (tau_n^J the Jaumann-rotated deviator of s_n), its
    equivalent shear stress q_tr = sqrt(tau_tr : tau_tr / 2) (= |tau_xy| in simple shear).  If
    q_tr <= tau_y the step is elastic, tau = tau_tr: below yield the fluid is a solid of modulus G and
    does not creep.  Beyond it the plastic shear rate gp solves the flow rule on the returned stress,
    q = q_tr - G dt gp = tau_y + K gp^n (Bingham: gp = (q_tr - tau_y) / (G dt + K) in closed form;
    Herschel-Bulkley by bisection), and tau = tau_tr q / q_tr: the return mapping of
    elasto-viscoplastic yield-stress fluids in MPM (Yue et al. 2015, ACM TOG 34(5):160).  Returns gp."""
    t = evp_trial(s, L, dt, G)
    q_tr = equivalent_shear(t)
    gp = 0.0
    scale = 1.0
    if q_tr > tau_y:
        gdt = G * dt
        if n == 1.0:
            gp = (q_tr - tau_y) / (gdt + K)
        else:
            hi = (q_tr - tau_y) / gdt  # f(hi) >= 0 > f(0): the root lies in [0, hi]
            lo = 0.0
            for _ in range(64):  # bisection: f is monotone, and Newton cycles on n < 1 (infinite slope at 0)
                gp = 0.5 * (lo + hi)
                if tau_y + K * gp ** n + gdt * gp > q_tr:
                    hi = gp
                else:
                    lo = gp
            gp = 0.5 * (lo + hi)
        scale = (q_tr - gdt * gp) / q_tr
    set_scaled_trial(s, t, scale, P)
    return gp
