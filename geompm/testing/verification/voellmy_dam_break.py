"""A dam break of a Voellmy flow on an incline against a depth-averaged reference computed here.

A block of viscous fluid, L0 long and H0 deep, rests against a wall on a bed inclined at beta with Voellmy
friction (mu, xi) and is released at t = 0 (gravity tilted, the bed the grid's y- wall, the dam the x- wall).
The reference is the depth-averaged (shallow) model of the same flow along the bed, x downslope:

    h_t + (h u)_x = 0
    (h u)_t + (h u^2 + g_n h^2 / 2)_x = g_t h - mu g_n h sgn(u) - g u |u| / xi + (4 nu h u_x)_x

g_t = g sin beta, g_n = g cos beta, nu = mu_v / rho: hydrostatic pressure across the depth, a plug velocity
u, Voellmy's basal law (Voellmy 1955; as in RAMMS, Christen et al. 2010) and the depth-integrated extensional
(membrane) stress of a Newtonian plug, 4 mu_v h u_x (the plane-strain extensional viscosity is 4 mu_v; the
term of thin viscous sheets, e.g. MacAyeal 1989's ice shelves), which a fluid stiff enough in shear to move
as a plug also carries along the flow.  Finite volumes on a fine grid: Rusanov fluxes, the membrane term
implicit (a tridiagonal solve for u each step), gravity then Coulomb friction (stopping, never reversing)
then Voellmy's term implicitly per cell
(|u'| + K |u'|^2 = |u|, K = g dt / (xi h)), a cell thinner than ``DRY`` m holding no momentum.  Compared:
the centroid's travel and speed and the front (the farthest point where the depth exceeds ``FRONT_DEPTH``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

G, BETA, MU, XI, RHO = 9.81, 30.0, 0.2, 100.0, 2000.0  # m/s2, deg, -, m/s2, kg/m3
VISCOSITY = 2000.0  # Pa s, as in the steady inflow (voellmy_inflow.py): a near plug
L0, H0, LENGTH = 1.0, 0.4, 6.0  # block length and depth, bed length [m]
DRY, FRONT_DEPTH = 1e-4, 0.02  # m


@njit(cache=True)
def _membrane(h, m, dt, dx, nu, u):
    """u from h u - dt (4 nu h u_x)_x = m, implicit (Thomas algorithm); dry cells hold u = 0."""
    n = h.shape[0]
    lower, diag, upper, rhs = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    c = dt / (dx * dx)
    for i in range(n):
        if h[i] <= DRY:
            diag[i] = 1.0
            continue
        kl = 4.0 * nu * 0.5 * (h[i - 1] + h[i]) if i > 0 and h[i - 1] > DRY else 0.0
        kr = 4.0 * nu * 0.5 * (h[i] + h[i + 1]) if i < n - 1 and h[i + 1] > DRY else 0.0
        lower[i], upper[i] = -c * kl, -c * kr
        diag[i] = h[i] + c * (kl + kr)
        rhs[i] = m[i]
    for i in range(1, n):
        w = lower[i] / diag[i - 1]
        diag[i] -= w * upper[i - 1]
        rhs[i] -= w * rhs[i - 1]
    u[n - 1] = rhs[n - 1] / diag[n - 1]
    for i in range(n - 2, -1, -1):
        u[i] = (rhs[i] - upper[i] * u[i + 1]) / diag[i]


@njit(cache=True)
def _advance(h, m, dx, t_end, gt, gn, mu, xi, nu, cfl):
    n = h.shape[0]
    t = 0.0
    flux_h = np.zeros(n + 1)
    flux_m = np.zeros(n + 1)
    u = np.zeros(n)
    while t < t_end:
        amax = 1e-12
        for i in range(n):
            u[i] = m[i] / h[i] if h[i] > DRY else 0.0
            a = abs(u[i]) + math.sqrt(gn * max(h[i], 0.0))
            if a > amax:
                amax = a
        dt = min(cfl * dx / amax, t_end - t)
        for f in range(1, n):  # Rusanov fluxes at inner faces; walls at both ends (no flux)
            l, r = f - 1, f
            fl_m = m[l] * u[l] + 0.5 * gn * h[l] * h[l]
            fr_m = m[r] * u[r] + 0.5 * gn * h[r] * h[r]
            a = max(abs(u[l]) + math.sqrt(gn * h[l]), abs(u[r]) + math.sqrt(gn * h[r]))
            flux_h[f] = 0.5 * (m[l] + m[r]) - 0.5 * a * (h[r] - h[l])
            flux_m[f] = 0.5 * (fl_m + fr_m) - 0.5 * a * (m[r] - m[l])
        flux_m[0] = 0.5 * gn * h[0] * h[0]  # the walls' pressure
        flux_m[n] = 0.5 * gn * h[n - 1] * h[n - 1]
        for i in range(n):
            h[i] -= dt / dx * (flux_h[i + 1] - flux_h[i])
            m[i] -= dt / dx * (flux_m[i + 1] - flux_m[i])
        if nu > 0.0:
            _membrane(h, m, dt, dx, nu, u)
            for i in range(n):
                m[i] = h[i] * u[i]
        for i in range(n):
            if h[i] <= DRY:
                m[i] = 0.0
                continue
            v = m[i] / h[i] + gt * dt
            s = max(abs(v) - mu * gn * dt, 0.0)  # Coulomb: stops, never reverses
            k = G * dt / (xi * h[i])
            s = (math.sqrt(1.0 + 4.0 * k * s) - 1.0) / (2.0 * k) if s > 0.0 else 0.0
            m[i] = h[i] * math.copysign(s, v)
        t += dt
    return t


def reference(times, cells: int = 1200, viscosity: float = VISCOSITY):
    """[(t, centroid x [m], centroid speed [m/s], front x [m])] of the depth-averaged model at ``times``."""
    b = math.radians(BETA)
    dx = LENGTH / cells
    x = (np.arange(cells) + 0.5) * dx
    h = np.where(x < L0, H0, 0.0)
    m = np.zeros(cells)
    out, now = [], 0.0
    for t in times:
        now += _advance(h, m, dx, t - now, G * math.sin(b), G * math.cos(b), MU, XI, viscosity / RHO, 0.4)
        wet = h > FRONT_DEPTH
        out.append((t, float((h * x).sum() / h.sum()), float(m.sum() / h.sum()),
                    float(x[wet].max() + 0.5 * dx) if wet.any() else 0.0))
    return out


def dam_break_case(h: float, end: float = 1.5, viscosity: float = VISCOSITY) -> dict:
    b = math.radians(BETA)
    return {"name": "voellmy_dam_break", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [LENGTH, 0.6], "cell_size": h},
            "time": {"end": end, "cfl": 0.4}, "gravity": [G * math.sin(b), -G * math.cos(b)],
            "solver": {"transfer": "apic"},
            "materials": {"debris": {"model": "newtonian", "density": RHO, "viscosity": viscosity,
                                     "sound_speed": 60.0}},
            "bodies": [{"material": "debris", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [L0, H0]},
                        "particles_per_cell": 2, "initial_stress": "geostatic"}],
            "boundaries": [{"type": "wall", "side": "x-"}, {"type": "wall", "side": "x+"},
                           {"type": "wall", "side": "y-", "condition": "voellmy", "friction": MU, "xi": XI}]}


def mpm_dam_break(h: float, times, viscosity: float = VISCOSITY):
    """[(t, centroid x, centroid speed along x, front x)] of the MPM run; the front from the depth of the
    particles' reference volumes binned in columns one cell wide."""
    from geompm.api import scene_from_dict
    from geompm.engine.scheduler import Simulation

    sim = Simulation(scene_from_dict(dam_break_case(h, max(times), viscosity)))
    st = sim.state
    out = []
    for t in times:
        while sim.time < t - 1e-12:
            sim.step(min(sim.stable_dt(), t - sim.time))
        m = st.p_mass
        xc = float((m * st.p_x[:, 0]).sum() / m.sum())
        uc = float((m * st.p_v[:, 0]).sum() / m.sum())
        cols = np.floor(st.p_x[:, 0] / h).astype(int)
        depth = np.bincount(cols, weights=st.p_vol0, minlength=int(LENGTH / h) + 2) / h
        wet = np.flatnonzero(depth > FRONT_DEPTH)
        out.append((t, xc, uc, float((wet.max() + 1) * h) if wet.size else 0.0))
    return out
