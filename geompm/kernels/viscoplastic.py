"""Viscoplastic regularisation of a rate-independent law (Duvaut & Lions 1972), one particle at a time.

A rate-independent elastoplastic law returns the elastic predictor sigma_tr to its yield surface at once
(sigma_inf, the inviscid return).  Duvaut-Lions viscoplasticity lets the stress reach the surface over a
relaxation time tau [s] instead: d sigma/dt = C : D - (sigma - sigma_inf) / tau, whose backward-Euler step
over dt is (Simo & Hughes 1998, Computational Inelasticity, sec. 2.7.2, eqs. 2.7.27-2.7.29)

    sigma_{n+1} = (sigma_tr + (dt / tau) sigma_inf) / (1 + dt / tau)
    q_{n+1}     = (q_n      + (dt / tau) q_inf)     / (1 + dt / tau)

for the stress and every internal variable q of the law (plastic strains, a softening law's state).  As
tau -> 0 it is the inviscid law; an elastic step (sigma_inf = sigma_tr) is unchanged.  The overstress is
about tau C : D_p, so it vanishes as the plastic flow slows: a slope at rest or creeping towards its limit
carries the inviscid strength.  What it adds is a time, hence (with the elastic wave speed c) a length c tau
over which a plastic band cannot form faster than the waves cross it: the rate-independent non-associated
law, whose perfectly plastic flow admits bands one cell wide (docs/slope-stability.md, The cause), becomes a
well-posed dynamic problem (Needleman 1988, Comput. Methods Appl. Mech. Eng. 67:69; Loret & Prevost 1990,
Comput. Methods Appl. Mech. Eng. 83:247).

Granular soil carries no viscous tension: where the relaxed stress would be tensile in the mean and more
tensile than the inviscid return (a particle at a free surface pulled apart faster than tau allows), the
inviscid return stands for that step (an overstress would otherwise hold a free-surface particle of a
cohesionless soil in tension).

The backend's law loops call ``keep_one`` before the law, the law's ``elastic_predictor`` and ``relax_one``
after it (backend/cpu_loops.py, backend/cuda_loops.py); ``p_old`` holds the particle's stress (6) and state at
the step's start.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True, inline="always")
def keep_one(s, state, old):
    """old[:6] = s, old[6:] = state: the particle's stress and state at the step's start."""
    for a in range(6):
        old[a] = s[a]
    for k in range(state.shape[0]):
        old[6 + k] = state[k]


@njit(cache=True, inline="always")
def relax_one(s, state, old, trial, r):
    """s = (trial + r s) / (1 + r), state = (old state + r state) / (1 + r): the Duvaut-Lions step with
    r = dt / tau (module docstring), s and state holding the inviscid return on entry."""
    w = 1.0 / (1.0 + r)
    mean_return = (s[0] + s[1] + s[2]) / 3.0
    mean = ((trial[0] + trial[1] + trial[2]) / 3.0 + r * mean_return) * w
    if mean > 0.0 and mean > mean_return:
        return  # no viscous tension: the inviscid return stands (module docstring)
    for a in range(6):
        s[a] = (trial[a] + r * s[a]) * w
    for k in range(state.shape[0]):
        state[k] = (old[6 + k] + r * state[k]) * w
