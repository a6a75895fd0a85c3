"""The per-item functions of the semi-implicit two-phase step's projection (docs/pore-water.md, The
semi-implicit step; schemes/saturated/semi_implicit.py).

After the explicit predictor (the two-phase step with the pore pressure p^n of the last step, drag implicit,
the stages acted) the pressure's increment dp = p^{n+1} - p^n makes the mixture's volume balance hold at the
end of the step (Chorin 1968's projection, incremental; the two-phase form of Kularathna et al. 2021, IJNME
122:1277, with the drag kept implicit in the correction):

    n/K_w dp/dt + div u^{n+1} = 0,   u = (1 - n) v_s + n v_w (the mixture's volume flux),

and on each phase, per unit volume (partial densities rho_s' = (1 - n) rho_s, rho_w' = n rho_w, drag q):

    rho_s' dv_s = dt (-(1 - n) grad dp + q dw),   rho_w' dv_w = dt (-n grad dp - q dw),   dw = dv_w - dv_s

so that du = -dt c grad dp with

    c = (1 - n)^2 / rho_s' + n^2 / rho_w' - dt q g^2 / (1 + dt q b),
    g = n / rho_w' - (1 - n) / rho_s',   b = 1 / rho_w' + 1 / rho_s'

(c -> 1 / rho_sat as q -> infinity: undrained, the mixture moves as one; c -> (1 - n)/rho_s + n/rho_w without
drag: the coefficient of CB-Geo's semi-implicit two-phase solver).  In weak form on the nodes I, with the
particles' quadrature, this is one symmetric positive definite system (pressure_system.py):

    sum_p V [ n/K_w N_I N_J + dt^2 c grad N_I . grad N_J ] dp_J = -dt sum_p V N_I div u*

with dp = 0 at the free surface and drained nodes (their fill below FREE_SURFACE_FILL; the particles there
hold p = 0, as in the explicit step) and the impermeable walls' natural condition (no flux).  The Laplacian in place of the discrete divergence of the discrete
gradient is the fractional step's own stabilisation of the equal-order pressure (Codina 2001, CMAME 190:1579):
it has no checkerboard mode.
"""

from numba import njit

from geompm.schemes.saturated.kernels import NODE_WATER, WATER

#: a node whose own particles' volume fraction sum N V / h^d is below this is outside the water for the
#: pressure system (dp = 0): the nodes past a wall that a quadratic or cubic stencil reaches, or a solid's
#: inside, are counted filled by the mirror (kernels.node_fill_one) but carry almost no support, and their
#: nearly empty rows made the quadratic step unstable (a hydrostatic column blew up within 50 steps); at 0.05
#: the column matches the explicit step's pressures row by row (docs/pore-water.md)
SUPPORT_MIN = 0.05


@njit(cache=True, inline="always")
def flux_terms_one(p, p_mass, p_wmass, p_drag, p_vol, p_n, p_divs, p_divw, p_material, table, dt, p_coef, p_store,
                   p_div):
    """Particle p's terms of the pressure equation: c (module docstring) [m3/kg], the water's
    storage n / K_w [1/Pa] and the predictor's volume-flux divergence (1 - n) div v_s + n div v_w [1/s]; all 0
    where the particle holds no water (dry or separated)."""
    mw = p_wmass[p]
    if mw <= 0.0:
        p_coef[p] = 0.0
        p_store[p] = 0.0
        p_div[p] = 0.0
        return
    v = p_vol[p]
    n = p_n[p]
    rs = p_mass[p] / v
    rw = mw / v
    q = p_drag[p] / v
    g = n / rw - (1.0 - n) / rs
    b = 1.0 / rw + 1.0 / rs
    p_coef[p] = (1.0 - n) * (1.0 - n) / rs + n * n / rw - dt * q * g * g / (1.0 + dt * q * b)
    p_store[p] = n / table[p_material[p], WATER.k_w]
    p_div[p] = (1.0 - n) * p_divs[p] + n * p_divw[p]


@njit(cache=True, inline="always")
def node_correct_one(i, g_mass, g_w, g_f, dt, mass_eps, g_vel, g_vw):
    """Node i: both phases' velocities corrected by the increment's forces (g_f[i, :d] the mixture's
    -sum V N grad dp, g_f[i, d:] the water's -sum V n N grad dp: pressure_system.increment_forces), the drag
    between them implicit:

        dw = dt (F_w / m_w - F_s / m_s) / (1 + dt c (1/m_w + 1/m_s)),   F_s = F - F_w
        dv_s = dt (F_s + c dw) / m_s,   dv_w = dt (F_w - c dw) / m_w
    """
    d = g_vel.shape[1]
    big = g_mass[i]
    mw = g_w[i, NODE_WATER.mass]
    ms = big - mw
    if ms <= mass_eps:
        return
    if mw <= mass_eps:
        for a in range(d):
            g_vel[i, a] += dt * g_f[i, a] / ms
        return
    c = g_w[i, NODE_WATER.drag]
    den = 1.0 + dt * c * (1.0 / mw + 1.0 / ms)
    for a in range(d):
        fw = g_f[i, d + a]
        fs = g_f[i, a] - fw
        dw = dt * (fw / mw - fs / ms) / den
        g_vel[i, a] += dt * (fs + c * dw) / ms
        g_vw[i, a] += dt * (fw - c * dw) / mw


@njit(cache=True, inline="always")
def node_join_one(i, g_mass, g_vel, g_vw, g_w, mass_eps, g_rel, g_rel0, g_vpre):
    """Node i: the corrected phases joined again, the mixture's velocity on g_vel (kept in g_vpre) and the
    relative velocity on g_rel (kept in g_rel0), for the stages to act once more (remap) and the split."""
    d = g_vel.shape[1]
    big = g_mass[i]
    mw = g_w[i, NODE_WATER.mass]
    if big <= mass_eps:
        return
    fw = mw / big
    for a in range(d):
        w = g_vw[i, a] - g_vel[i, a] if mw > mass_eps else 0.0
        g_vel[i, a] += fw * w
        g_vpre[i, a] = g_vel[i, a]
        g_rel[i, a] = w
        g_rel0[i, a] = w


@njit(cache=True, inline="always")
def node_unknown_one(i, g_fill, g_w, band, centre, fill_min, mass_eps, cell_volume, g_unknown):
    """Node i: 1 where its pressure increment is unknown (water around it, its own support at least
    SUPPORT_MIN, its fill at least fill_min: not the free surface or a drained boundary), 0 where dp = 0 (the
    drained particles around it hold p = 0: kernels.add_increment_one)."""
    wet = (g_w[i, NODE_WATER.mass] > mass_eps and band[i, centre] > 0.0
           and g_w[i, NODE_WATER.volume] >= SUPPORT_MIN * cell_volume)
    g_unknown[i] = 1 if wet and g_fill[i] >= fill_min else 0


@njit(cache=True, inline="always")
def affine_flux_one(p, p_C, p_Cw, p_n, p_wmass):
    """Particle p after the G2P (APIC): the isotropic part of the mixture's volume-flux divergence its
    affine matrices carry, r = (1 - n) tr C_s + n tr C_w, taken off both (C -= r/d I).  The projection makes
    the grid's flux divergence-free only approximately; the affine matrices would carry the remainder to the
    next step's P2G, where the projection would remove it again and add its increment to the pressure each
    step: a saturated APIC flow drifted into suction (-20 kPa in 0.4 s on the 2D flume, where PIC and the
    explicit step held -4 kPa)."""
    if p_wmass[p] <= 0.0:
        return
    d = p_C.shape[1]
    n = p_n[p]
    r = 0.0
    for a in range(d):
        r += (1.0 - n) * p_C[p, a, a] + n * p_Cw[p, a, a]
    r /= d
    for a in range(d):
        p_C[p, a, a] -= r
        p_Cw[p, a, a] -= r
