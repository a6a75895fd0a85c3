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

from ..kernels.voigt import jaumann_increment


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
def evp_fluid_stress(s, L, P, mu, G, dt):
    """Elasto-viscoplastic update of one particle: s <- -P I + tau_{n+1} (Voigt, in place), with

        tau_{n+1} = (tau_n^J + 2 G D' dt) / (1 + G dt / mu),

    the backward-Euler step of the Maxwell model dtau/dt = 2 G D' - (G / mu) tau (tau_n^J the
    Jaumann-rotated deviator of s_n, mu = mu_eff(gamma_dot) of the law at the current rate).  It is
    stable at any dt; its steady state under a constant rate is tau = 2 mu D', the viscous law; below
    yield (mu large, relaxation time mu / G long) the fluid is an elastic solid of shear modulus G.
    The elasto-viscoplastic form of yield-stress fluids in MPM: Yue et al. 2015, ACM TOG 34(5):160."""
    jz = jaumann_increment(s, L, dt)
    r0, r1, r2 = s[0] + jz[0], s[1] + jz[1], s[2] + jz[2]
    m = (r0 + r1 + r2) / 3.0
    tr3 = (L[0, 0] + L[1, 1] + L[2, 2]) / 3.0
    k = 1.0 / (1.0 + G * dt / mu) if mu > 0.0 else 0.0
    g2 = 2.0 * G * dt
    s0 = k * (r0 - m + g2 * (L[0, 0] - tr3))
    s1 = k * (r1 - m + g2 * (L[1, 1] - tr3))
    s2 = k * (r2 - m + g2 * (L[2, 2] - tr3))
    s3 = k * (s[3] + jz[3] + G * dt * (L[0, 1] + L[1, 0]))
    s4 = k * (s[4] + jz[4] + G * dt * (L[1, 2] + L[2, 1]))
    s5 = k * (s[5] + jz[5] + G * dt * (L[0, 2] + L[2, 0]))
    s[0] = s0 - P
    s[1] = s1 - P
    s[2] = s2 - P
    s[3] = s3
    s[4] = s4
    s[5] = s5


@njit(cache=True, inline="always")
def yield_fluid_stress(s, L, P, mu, G, dt):
    """The explicit viscous stress (G = 0) or the elasto-viscoplastic update (G > 0)."""
    if G > 0.0:
        evp_fluid_stress(s, L, P, mu, G, dt)
    else:
        set_fluid_stress(s, L, P, mu)


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
    jz = jaumann_increment(s, L, dt)
    r0, r1, r2 = s[0] + jz[0], s[1] + jz[1], s[2] + jz[2]
    m = (r0 + r1 + r2) / 3.0
    tr3 = (L[0, 0] + L[1, 1] + L[2, 2]) / 3.0
    g2 = 2.0 * G * dt
    t0 = r0 - m + g2 * (L[0, 0] - tr3)
    t1 = r1 - m + g2 * (L[1, 1] - tr3)
    t2 = r2 - m + g2 * (L[2, 2] - tr3)
    t3 = s[3] + jz[3] + G * dt * (L[0, 1] + L[1, 0])
    t4 = s[4] + jz[4] + G * dt * (L[1, 2] + L[2, 1])
    t5 = s[5] + jz[5] + G * dt * (L[0, 2] + L[2, 0])
    q_tr = math.sqrt(0.5 * (t0 * t0 + t1 * t1 + t2 * t2) + t3 * t3 + t4 * t4 + t5 * t5)
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
    s[0] = scale * t0 - P
    s[1] = scale * t1 - P
    s[2] = scale * t2 - P
    s[3] = scale * t3
    s[4] = scale * t4
    s[5] = scale * t5
    return gp
