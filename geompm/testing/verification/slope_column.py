"""The infinite slope's reference without the MPM: a one-dimensional elastoplastic column in simple shear.

An infinite slope (docs/slope-stability.md, Verification: the infinite slope) is uniform along the slope, so
its exact motion is a function of the depth alone: v_x(y, t), v_y(y, t) with D_xx = D_zz = 0.  This module
integrates that column with the strength-reduction trial's own schedule, damping and criterion, so that the
factor a trial of finite length can give is known before the MPM is compared with it:

    rho dv/dt = d sigma_xy/dy + rho g_x - zeta rho v_x,     rho dv/dt = d sigma_yy/dy + rho g_y - zeta rho v_y

on ``elements`` two-node elements of one point each (lumped mass, the base node fixed, the top free), the
velocity gradient of each element L = [[0, dv_x/dy, 0], [0, dv_y/dy, 0], [0, 0, 0]] over its current
thickness, and its stress advanced by the law's own ``particle_stress`` (the return the engine runs), from
the state the MPM trial starts in (no stress, gravity on at t = 0) and under the same strength schedule:
F0 for the first quarter, a ramp to F over the second, F held for the second half (stability/trial.py).
The velocity is damped as the trials' artificial stage damps the particles, v <- v exp(-zeta dt), and with
``viscoplastic_time`` the law is regularised as the engine regularises it (kernels/viscoplastic.py).  The
trial's criterion (stability/criterion.judge) reads the largest displacement (the top node's) at T/2, 3T/4
and T.  With ``elements`` and the step refined the column converges: it has no spatial noise to lose
strength to (one point per element, D_xx = 0 exactly), so its factor is the continuum's for that trial.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from geompm.kernels.viscoplastic import keep_one, relax_one
from geompm.stability.criterion import judge
from geompm.stability.trial import SERIES_ROWS, strength_schedule

#: strength levels a ramp is tabulated at (the law's parameters packed once per level)
LEVELS = 401


@njit
def _run(law, predictor, r, prm_levels, f_levels, times, factors, elements, depth, rho0, gx, gy, zeta, dt, nsteps,
         out_every, nstate, series):
    n = elements
    dz0 = depth / n
    y = np.empty(n + 1)
    for j in range(n + 1):
        y[j] = j * dz0
    u = np.zeros((n + 1, 2))
    v = np.zeros((n + 1, 2))
    m_el = rho0 * dz0
    m = np.full(n + 1, m_el)
    m[0] = 0.5 * m_el
    m[n] = 0.5 * m_el
    s = np.zeros((n, 6))
    state = np.zeros((n, nstate))
    old = np.zeros(6 + nstate)
    L = np.zeros((3, 3))
    f = np.zeros((n + 1, 2))
    decay = math.exp(-zeta * dt)
    t = 0.0
    row = 0
    nlev = f_levels.shape[0]
    for step in range(nsteps + 1):
        if step % out_every == 0 and row < series.shape[0]:
            umax = 0.0
            ek = 0.0
            for j in range(n + 1):
                umax = max(umax, math.sqrt(u[j, 0] ** 2 + u[j, 1] ** 2))
                ek += 0.5 * m[j] * (v[j, 0] ** 2 + v[j, 1] ** 2)
            series[row, 0] = t
            series[row, 1] = umax
            series[row, 2] = ek
            row += 1
        if step == nsteps:
            break
        # the strength level at this time (piecewise linear schedule, nearest tabulated level)
        fac = np.interp(t, times, factors)
        k = 0
        if nlev > 1:
            k = int(round((fac - f_levels[0]) / (f_levels[nlev - 1] - f_levels[0]) * (nlev - 1))) if f_levels[nlev - 1] != f_levels[0] else 0
            k = min(max(k, 0), nlev - 1)
        prm = prm_levels[k]
        # nodal forces from the elements' stresses (compression negative)
        for j in range(n + 1):
            f[j, 0] = m[j] * gx
            f[j, 1] = m[j] * gy
        for e in range(n):
            f[e, 0] += s[e, 3]
            f[e, 1] += s[e, 1]
            f[e + 1, 0] -= s[e, 3]
            f[e + 1, 1] -= s[e, 1]
        for j in range(1, n + 1):
            v[j, 0] = (v[j, 0] + dt * f[j, 0] / m[j]) * decay
            v[j, 1] = (v[j, 1] + dt * f[j, 1] / m[j]) * decay
        for j in range(1, n + 1):
            u[j, 0] += dt * v[j, 0]
            u[j, 1] += dt * v[j, 1]
        for e in range(n):
            dz = dz0 + u[e + 1, 1] - u[e, 1] - dt * (v[e + 1, 1] - v[e, 1])  # the thickness at the step's start
            L[0, 1] = (v[e + 1, 0] - v[e, 0]) / dz
            L[1, 1] = (v[e + 1, 1] - v[e, 1]) / dz
            rho = m_el / (dz0 + u[e + 1, 1] - u[e, 1])
            if r > 0.0:
                keep_one(s[e], state[e], old)
                law(prm, dt, L, rho, s[e], state[e])
                relax_one(s[e], state[e], old, predictor(prm, dt, L, rho, old), r)
            else:
                law(prm, dt, L, rho, s[e], state[e])
        t += dt
    return row


def column_series(law_cls, params: dict, factor: float, *, slope: float = 20.0, depth: float = 1.0,
                  elements: int = 100, duration: float = 2.0, damping_rate: float | None = None,
                  cfl: float = 0.4, viscoplastic_time: float | None = None) -> dict:
    """The column's trial at ``factor``: {'time', 'max_displacement', 'kinetic_energy'} at SERIES_ROWS + 1
    times, as a trial's series.csv.  ``params``: the law's JSON parameters (density included);
    ``damping_rate`` [1/s] default 40 / duration (stability/search.py's default); ``viscoplastic_time`` [s]: the
    laws' Duvaut-Lions regularisation as the engine runs it (kernels/viscoplastic.py), default none."""
    p = law_cls.Params(**params)
    rate = 40.0 / duration if damping_rate is None else damping_rate
    times, factors = (np.array(a, float) for a in strength_schedule(factor, duration))
    f_levels = np.linspace(factors[0], factors[-1], LEVELS if factors[0] != factors[-1] else 1)
    prm_levels = np.array([law_cls(p.model_copy(update=law_cls.strength_reduced(p, float(f)))).prm
                           for f in f_levels])
    rho0 = float(p.density)
    b = math.radians(slope)
    c = float(law_cls.particle_wave_speed(prm_levels[0], rho0))
    dt_out = duration / SERIES_ROWS
    dz = depth / elements
    per_out = max(1, math.ceil(dt_out / (cfl * dz / c)))
    dt = dt_out / per_out
    nsteps = per_out * SERIES_ROWS
    series = np.zeros((SERIES_ROWS + 1, 3))
    r = dt / viscoplastic_time if viscoplastic_time else 0.0
    _run(law_cls.particle_stress, law_cls.elastic_predictor, r, prm_levels, f_levels, times, factors, elements,
         depth, rho0, 9.81 * math.sin(b), -9.81 * math.cos(b), rate, dt, nsteps, per_out, max(1, len(law_cls.state_vars)), series)
    return {"time": series[:, 0], "max_displacement": series[:, 1], "kinetic_energy": series[:, 2]}


def column_factor(law_cls, params: dict, *, low: float, high: float, tolerance: float = 1e-3, ratio: float = 0.5,
                  floor: float = 1e-4, **kw) -> tuple[float, list]:
    """The column's factor of safety: bisection between a standing ``low`` and a failing ``high`` until the
    bracket is ``tolerance`` wide (relative), each trial judged as the search judges (criterion.judge, with
    the displacement floor ``floor`` [m]).  Returns (the bracket's middle, [(F, judge dict), ...])."""
    trials = []
    for f in (low, high):
        trials.append((f, judge(column_series(law_cls, params, f, **kw), ratio, floor)))
    if trials[0][1]["failed"] or not trials[1][1]["failed"]:
        raise ValueError(f"the bracket [{low}, {high}] does not hold the column's limit: {trials}")
    while (high - low) > tolerance * low:
        mid = 0.5 * (low + high)
        j = judge(column_series(law_cls, params, mid, **kw), ratio, floor)
        trials.append((mid, j))
        if j["failed"]:
            high = mid
        else:
            low = mid
    return 0.5 * (low + high), trials
