"""The kernels of saturated soil: one point, two velocities (solid and water), explicit in time.

Each particle carries solids and the water in its pores (docs/pore-water.md for the derivation and the
references: Zienkiewicz et al. 1980; Bandara & Soga 2015, Computers and Geotechnics 63:199). Per particle
(V volume, n porosity, s 1 saturated / 0 dry, p pore pressure, compression positive):

    water mass    m_w = s n rho_w V
    drag          D V = s n^2 (mu_w / kappa(n)) V      [kg/s]  (Darcy: n (v_w - v_s) = -(kappa/mu_w) grad p ...)
    total stress  sigma = sigma' - p I                 (the law updates sigma', unchanged)

On the nodes I, from the particles' shape functions N and gradients grad N:

    mixture  (m_s + m_w) a_mix = -sum V sigma grad N + (m_s + m_w) g (+ boundary and obstacle forces)
    water    m_w a_w = sum V s n p grad N + m_w g - c (v_w - v_s),   c = sum N D V

The relative velocity w = v_w - v_s takes the drag implicitly (node_relative): the step is then free of the
drag's explicit limit 2 m_w / c (docs/pore-water.md, The time step); gravity cancels from it. After the
stages have acted on the mixture, node_split gives the solid and the water their velocities; the solid's
goes through the ordinary G2P (the law sees its velocity gradient L), the water's through water_g2p, and
the pore pressure follows the water's mass balance (pressure_increment, at the particles before they move):

    dp = -dt K_w / n [(1 - n) tr L + n div v_w]

with p = 0 on drained particles (at the free surface, at a drained boundary, separated or dry); the porosity
follows the skeleton's volume, n = 1 - (1 - n0) V0 / V. Each particle carries its own sum of increments
(p_pore_carried); the pressure that acts on the grid is that sum seen through the grid, S p_pore_carried
(a scatter of V and V p, smooth_node_one, smooth_gather_one), and the increment passes through the same S:
the exchange of energy between the pressure and the velocities then balances (docs/pore-water.md).

Every pass but the two scatters is a per-item function here (``*_one``, of one particle or one node) that
the backend's generated loops run, one source for the CPU and the GPU (Backend.each; backend/item_loops.py,
backend/cuda_loops.py); the scatters add into the grid as the solid's P2G does, with private grids per chunk
on the CPU (schemes/saturated/cpu_scatter.py) and atomics on the GPU (schemes/saturated/cuda.py).
"""

from numba import njit

from geompm.contract.layout import param_layout
from geompm.kernels.shape import LINEAR, axis_stencil

#: a material's row of the pore-water table (schemes/saturated/setup.py): the water's density [kg/m3], bulk
#: modulus [Pa] and viscosity [Pa s], the initial porosity [-], the intrinsic permeability at it [m2], 1 for
#: Kozeny-Carman's update of it (0: constant), the porosity past which the skeleton is separated [-], the
#: cavitation pressure [Pa, gauge]
WATER = param_layout("rho_w", "k_w", "mu_w", "n0", "kappa0", "kozeny", "n_max", "p_cav")
#: a node's row of the water's grid ``g_w`` (water_p2g): its mass [kg], momentum [kg m/s] and internal force
#: sum V s n p grad N [N] per axis (z unused in 2D), the drag coefficient c = sum N D V [kg/s], the
#: particles' volume sum N V [m^d] (the free-surface fill), and sum N V p and sum N V sigma (Voigt) of the
#: acting pore pressure and total stress [Pa m^d] (the contact's pore water, node_pore_one)
NODE_WATER = param_layout("mass", "mom_x", "mom_y", "mom_z", "force_x", "force_y", "force_z", "drag", "volume",
                          "pv", "sv_xx", "sv_yy", "sv_zz", "sv_xy", "sv_yz", "sv_xz")
#: the row's width, and the offsets of the per-axis columns: ``g_w[i, MOM + a]`` is the momentum along axis a
WATER_WIDTH = len(NODE_WATER)
MOM = NODE_WATER.mom_x
FORCE = NODE_WATER.force_x
PV = NODE_WATER.pv  # g_w[i, PV]: sum N V p; g_w[i, PV + 1 + k]: sum N V sigma_k

#: a row of the water boundaries ``walls`` (schemes/saturated/setup.wall_row): a point of the wall's plane [m],
#: its unit normal into the material, the layer [m] of nodes it binds, 1 for a drained wall, 2 for one that holds
#: a head (water crosses both; the particles at a held head keep their pressure), 0 impermeable
WALL = param_layout("px", "py", "pz", "nx", "ny", "nz", "layer", "drained")
#: a particle whose interpolated node fill (the particles' volume fraction around the nodes, the body
#: mirrored in impermeable walls: node_fill) is below this is at the free surface or a drained boundary:
#: its pore pressure is 0 (docs/pore-water.md). On a flat surface it flags the particles within about half
#: a cell of it, for 1 to 4 particles per cell and linear, quadratic and cubic shape functions
FREE_SURFACE_FILL = 0.78


@njit(cache=True, inline="always")
def permeability(row, n):
    """kappa(n) [m2]: kappa0, or Kozeny-Carman kappa0 n^3 (1 - n0)^2 / (n0^3 (1 - n)^2)."""
    if row[WATER.kozeny] == 0.0:
        return row[WATER.kappa0]
    n0 = row[WATER.n0]
    return row[WATER.kappa0] * (n * n * n * (1.0 - n0) * (1.0 - n0)) / (n0 * n0 * n0 * (1.0 - n) * (1.0 - n))


@njit(cache=True, inline="always")
def wet(row, sat, n):
    """1.0 where the particle holds water under pressure: saturated and not separated (n <= n_max)."""
    return sat if n <= row[WATER.n_max] else 0.0


@njit(cache=True, inline="always")
def prepare_one(p, p_stress, p_pore, p_n, p_sat, p_vol, p_material, table, p_total, p_wmass, p_drag):
    """Particle p: the total stress sigma' - p I, the water mass and the drag coefficient D V."""
    row = table[p_material[p]]
    n = p_n[p]
    s = wet(row, p_sat[p], n)
    pp = s * p_pore[p]
    for k in range(6):
        p_total[p, k] = p_stress[p, k]
    for k in range(3):
        p_total[p, k] -= pp
    p_wmass[p] = s * n * row[WATER.rho_w] * p_vol[p]
    p_drag[p] = s * n * n * row[WATER.mu_w] / permeability(row, n) * p_vol[p] if s > 0.0 else 0.0


@njit(cache=True, inline="always")
def particle_stencil(p_x, p, origin, kind, inv_h, d):
    """Particle p's stencil: its base node (3-tuple) and the weights and derivatives along x, y and z
    (kernels/shape.axis_stencil); in 2D z is one node of weight 1."""
    bx, wx, dx = axis_stencil((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h)
    by, wy, dy = axis_stencil((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h)
    zc = (p_x[p, 2] - origin[2]) * inv_h if d == 3 else 0.0
    bz, wz, dz = axis_stencil(zc, kind if d == 3 else LINEAR, inv_h)
    return (bx, by, bz), wx, dx, wy, dy, wz, dz


@njit(cache=True, inline="always")
def node_index(b, lo, nloc, i, j, k, d):
    if d == 2:
        return (b[0] + i - lo[0]) * nloc[1] + (b[1] + j - lo[1])
    return ((b[0] + i - lo[0]) * nloc[1] + (b[1] + j - lo[1])) * nloc[2] + (b[2] + k - lo[2])


@njit(cache=True, inline="always")
def water_scalars_one(p, p_wmass, p_drag, p_vol, p_n, p_pore, p_sat, p_material, table):
    """Particle p's scalars in the water's P2G: (m_w, s n p V (its internal force per grad N), D V, V, s p V)."""
    row = table[p_material[p]]
    spv = wet(row, p_sat[p], p_n[p]) * p_pore[p] * p_vol[p]
    return (p_wmass[p], p_n[p] * spv, p_drag[p], p_vol[p], spv)


@njit(cache=True, inline="always")
def node_pore_one(i, g_w, g_pore):
    """Node i's pore water for the contact rules (contract/stages.NODE_PORE): the particles' volume-weighted
    pore pressure and total stress around it, sum N V f / sum N V (0 where no particle reaches)."""
    v = g_w[i, NODE_WATER.volume]
    inv = 1.0 / v if v > 0.0 else 0.0
    for k in range(7):
        g_pore[i, k] = g_w[i, PV + k] * inv


@njit(cache=True, inline="always")
def node_mixture_one(i, g_mass, g_mom, g_w, mass_eps, g_rel):
    """Node i: the mixture on the solid's arrays and the relative velocity before the step.  In: g_mass,
    g_mom of the solid P2G (g_force, from the total stress, is already the mixture's internal force), g_w
    of water_p2g.  Out: g_rel <- w = v_w - v_s, g_mass <- m_s + m_w, g_mom <- m_s v_s + m_w v_w."""
    d = g_mom.shape[1]
    ms = g_mass[i]
    mw = g_w[i, NODE_WATER.mass]
    for a in range(d):
        g_rel[i, a] = g_w[i, MOM + a] / mw - g_mom[i, a] / ms if ms > mass_eps and mw > mass_eps else 0.0
        g_mom[i, a] += g_w[i, MOM + a]
    g_mass[i] = ms + mw


@njit(cache=True, inline="always")
def node_relative_one(i, g_mass, g_vel, g_vel_old, g_w, gravity, dt, mass_eps, g_rel, g_rel0):
    """Node i: the relative velocity after the step, w' = v_w' - v_s', drag implicit, from the mixture's
    acceleration a = (v' - v) / dt once gravity, the loads and the damping have acted on it (g_vel,
    g_vel_old) and the water's own force (m_w a_w = F_w + m_w g - c w'):

        w' (m_s m_w + dt c M) = m_s m_w w + dt M (F_w + m_w (g - a)),   M = m_s + m_w
    """
    d = g_vel.shape[1]
    big = g_mass[i]
    mw = g_w[i, NODE_WATER.mass]
    ms = big - mw
    for a in range(d):
        g_rel0[i, a] = g_rel[i, a]
    if ms > mass_eps and mw > mass_eps:
        den = ms * mw + dt * g_w[i, NODE_WATER.drag] * big
        for a in range(d):
            acc = (g_vel[i, a] - g_vel_old[i, a]) / dt
            rhs = ms * mw * g_rel[i, a] + dt * big * (g_w[i, FORCE + a] + mw * (gravity[a] - acc))
            g_rel[i, a] = rhs / den
    else:
        for a in range(d):
            g_rel[i, a] = 0.0


@njit(cache=True, inline="always")
def node_snapshot_one(i, g_mass, g_vel, g_vel_old, g_w, gravity, dt, mass_eps, g_rel, g_rel0, g_vpre):
    """Node i once gravity, the loads and the damping have acted on the mixture: node_relative_one, and the
    mixture's velocity kept in g_vpre before the boundaries and obstacles act (node_split_one finds what they
    changed)."""
    node_relative_one(i, g_mass, g_vel, g_vel_old, g_w, gravity, dt, mass_eps, g_rel, g_rel0)
    for a in range(g_vel.shape[1]):
        g_vpre[i, a] = g_vel[i, a]


@njit(cache=True, inline="always")
def node_remap_one(i, g_mass, g_mom, g_w, mass_eps, g_vel, g_rel, g_rel0, g_vpre):
    """Node i, MUSL: the phases' momenta re-mapped from their updated particle velocities (the solid's on
    g_mass, g_mom, the water's in g_w) to the mixture (node_mixture_one), its velocity g_vel and the relative
    velocity g_rel, both kept (g_vpre, g_rel0) for node_split_one to find what the boundaries changed."""
    node_mixture_one(i, g_mass, g_mom, g_w, mass_eps, g_rel)
    m = g_mass[i]
    for a in range(g_vel.shape[1]):
        g_vel[i, a] = g_mom[i, a] / m if m > mass_eps else 0.0
        g_vpre[i, a] = g_vel[i, a]
        g_rel0[i, a] = g_rel[i, a]


@njit(cache=True)
def node_of(i, lo, nloc, d):
    """Global (ix, iy, iz) of window node i."""
    if d == 2:
        return i // nloc[1] + lo[0], i % nloc[1] + lo[1], 0
    return i // (nloc[1] * nloc[2]) + lo[0], (i // nloc[2]) % nloc[1] + lo[1], i % nloc[2] + lo[2]


@njit(cache=True)
def mirrored(x0, x1, x2, walls, k):
    """(x0, x1, x2) reflected in wall k's plane, and the signed distance from the plane."""
    dist = ((x0 - walls[k, WALL.px]) * walls[k, WALL.nx] + (x1 - walls[k, WALL.py]) * walls[k, WALL.ny]
            + (x2 - walls[k, WALL.pz]) * walls[k, WALL.nz])
    return (x0 - 2.0 * dist * walls[k, WALL.nx], x1 - 2.0 * dist * walls[k, WALL.ny],
            x2 - 2.0 * dist * walls[k, WALL.nz], dist)


@njit(cache=True)
def raw_fill_at(x0, x1, x2, g_w, origin, h, lo, nloc, d, cell_volume):
    """The particles' volume fraction at the window node nearest x (0 outside the window)."""
    ix = int(round((x0 - origin[0]) / h)) - lo[0]
    iy = int(round((x1 - origin[1]) / h)) - lo[1]
    iz = 0
    if d == 3:
        iz = int(round((x2 - origin[2]) / h)) - lo[2]
        if iz < 0 or iz >= nloc[2]:
            return 0.0
    if ix < 0 or iy < 0 or ix >= nloc[0] or iy >= nloc[1]:
        return 0.0
    idx = ix * nloc[1] + iy
    if d == 3:
        idx = idx * nloc[2] + iz
    return g_w[idx, NODE_WATER.volume] / cell_volume


@njit(cache=True)
def one_node_fill(i, g_w, walls, origin, h, lo, nloc, d, cell_volume):
    ix, iy, iz = node_of(i, lo, nloc, d)
    x0 = origin[0] + ix * h
    x1 = origin[1] + iy * h
    x2 = origin[2] + iz * h if d == 3 else 0.0
    f = g_w[i, NODE_WATER.volume] / cell_volume
    reach = 2.0 * h  # beyond this no node of a mirrored particle's stencil comes back
    for k in range(walls.shape[0]):
        if walls[k, WALL.drained] == 1.0:  # a drained face is a free surface; a held head's is not (2)
            continue
        y0, y1, y2, dk = mirrored(x0, x1, x2, walls, k)
        if dk >= reach:
            continue
        f += raw_fill_at(y0, y1, y2, g_w, origin, h, lo, nloc, d, cell_volume)
        for j in range(k + 1, walls.shape[0]):
            if walls[j, WALL.drained] == 1.0:
                continue
            z0, z1, z2, dj = mirrored(y0, y1, y2, walls, j)
            if abs(dj) < reach:
                f += raw_fill_at(z0, z1, z2, g_w, origin, h, lo, nloc, d, cell_volume)
    return f


@njit(cache=True, inline="always")
def node_fill_one(i, g_w, g_solid, walls, origin, h, lo, nloc, cell_volume, g_fill):
    """Node i's fill: the particles' volume fraction, with the body mirrored in every impermeable wall
    (and in each pair of them, for corners) and the impermeable rigid solids' volume fraction g_solid[i, 0]
    (solids.py) added, so that a wall, an obstacle or the terrain is not taken for a free surface while the
    body's real free surface still is (docs/pore-water.md, Free surface)."""
    g_fill[i] = one_node_fill(i, g_w, walls, origin, h, lo, nloc, len(lo), cell_volume) + g_solid[i, 0]


@njit(cache=True, inline="always")
def node_split_one(i, g_mass, g_vel, g_vpre, g_w, g_rel, g_rel0, g_solid, walls, origin, h, lo, nloc, gravity, dt,
                   mass_eps, g_vw, g_vold, g_vwold):
    """Node i: solid and water velocities from the mixture's after the stages (g_vel, in place -> the solid's;
    g_vw <- the water's).

    ``walls`` rows (docs/pore-water.md): point (3), unit normal into the material (3), layer [m], drained.
    At an impermeable wall's node the relative velocity loses its normal part (no flow across); at a
    drained wall's node the wall's rule binds the solid and the water crosses freely, its normal relative
    velocity advanced against the held solid, w_n' (m_w + dt c) = m_w w_n + dt (F_w + m_w g)_n (the
    mixture's acceleration there is the wall's to stop, not the water's); at a node that a stage changed
    elsewhere (an obstacle) both phases take the stage's velocity, except on or inside an impermeable rigid
    solid (g_solid[i, 2:5] its normal, solids.py), where w loses its normal part as at an impermeable wall,
    and at a drained solid's contact node (g_solid[i, 1] = 1: a permeable dam), where the grains take the
    stage's velocity and the water keeps its velocity relative to them. g_rel0: the relative velocity before the step.
    """
    d = g_vel.shape[1]
    nw = walls.shape[0]
    big = g_mass[i]
    if big <= mass_eps:
        for a in range(d):
            g_vw[i, a] = 0.0
            g_vwold[i, a] = 0.0
        return
    fw_old = g_w[i, NODE_WATER.mass] / big
    for a in range(d):
        g_vwold[i, a] = g_vold[i, a] + (1.0 - fw_old) * g_rel0[i, a]
        g_vold[i, a] -= fw_old * g_rel0[i, a]
    ix, iy, iz = node_of(i, lo, nloc, d)
    w0 = g_rel[i, 0]
    w1 = g_rel[i, 1]
    w2 = g_rel[i, 2] if d == 3 else 0.0
    bound = False
    drained = False
    t0 = t1 = t2 = 0.0  # the part of w tangential to a drained wall
    for k in range(nw):
        dist = ((origin[0] + ix * h - walls[k, WALL.px]) * walls[k, WALL.nx]
                + (origin[1] + iy * h - walls[k, WALL.py]) * walls[k, WALL.ny])
        if d == 3:
            dist += (origin[2] + iz * h - walls[k, WALL.pz]) * walls[k, WALL.nz]
        if dist <= walls[k, WALL.layer]:
            bound = True
            wn = w0 * walls[k, WALL.nx] + w1 * walls[k, WALL.ny] + w2 * walls[k, WALL.nz]
            if walls[k, WALL.drained] > 0.0:
                drained = True
                mw = g_w[i, NODE_WATER.mass]
                old = g_rel0[i, 0] * walls[k, WALL.nx] + g_rel0[i, 1] * walls[k, WALL.ny]
                push = ((g_w[i, FORCE] + mw * gravity[0]) * walls[k, WALL.nx]
                        + (g_w[i, FORCE + 1] + mw * gravity[1]) * walls[k, WALL.ny])
                if d == 3:
                    old += g_rel0[i, 2] * walls[k, WALL.nz]
                    push += (g_w[i, FORCE + 2] + mw * gravity[2]) * walls[k, WALL.nz]
                held = (mw * old + dt * push) / (mw + dt * g_w[i, NODE_WATER.drag]) if mw > mass_eps else 0.0
                t0, t1, t2 = w0 - wn * walls[k, WALL.nx], w1 - wn * walls[k, WALL.ny], w2 - wn * walls[k, WALL.nz]
                w0, w1, w2 = t0 + held * walls[k, WALL.nx], t1 + held * walls[k, WALL.ny], t2 + held * walls[k, WALL.nz]
            else:
                w0 -= wn * walls[k, WALL.nx]
                w1 -= wn * walls[k, WALL.ny]
                w2 -= wn * walls[k, WALL.nz]
    sn0, sn1, sn2 = g_solid[i, 2], g_solid[i, 3], g_solid[i, 4]
    if sn0 != 0.0 or sn1 != 0.0 or sn2 != 0.0:  # on or inside an impermeable solid: no flow across it
        bound = True
        wn = w0 * sn0 + w1 * sn1 + w2 * sn2
        w0 -= wn * sn0
        w1 -= wn * sn1
        w2 -= wn * sn2
    changed = False
    for a in range(d):
        if g_vel[i, a] != g_vpre[i, a]:
            changed = True
    if changed and not bound:
        if g_solid[i, 1] > 0.0:
            drained = True  # a permeable solid holds the grains at its velocity; the water keeps w
        else:
            w0 = w1 = w2 = 0.0
    mw = g_w[i, NODE_WATER.mass]
    fw = mw / big
    fs = 1.0 - fw
    if drained:
        g_vel[i, 0] -= fw * t0
        g_vel[i, 1] -= fw * t1
        g_vw[i, 0] = g_vel[i, 0] + w0
        g_vw[i, 1] = g_vel[i, 1] + w1
        if d == 3:
            g_vel[i, 2] -= fw * t2
            g_vw[i, 2] = g_vel[i, 2] + w2
    else:
        g_vw[i, 0] = g_vel[i, 0] + fs * w0
        g_vw[i, 1] = g_vel[i, 1] + fs * w1
        g_vel[i, 0] -= fw * w0
        g_vel[i, 1] -= fw * w1
        if d == 3:
            g_vw[i, 2] = g_vel[i, 2] + fs * w2
            g_vel[i, 2] -= fw * w2


@njit(cache=True, inline="always")
def water_g2p_one(p, tag, p_x, p_vw, p_Cw, affine, apic_dinv, flip, p_divw, p_divs, p_fill, g_vw, g_vwold, g_vs, g_fill,
                  origin, h, kind, lo, nloc):
    """Particle p (``tag``: the stencil's S nodes per axis, kernels/stencil.py): the water's particle
    velocity, its affine matrix (with ``affine``: C_w = B_w D^-1 as the solid's
    APIC, B_w = sum N v_wI (x_I - x_p)^T, or the velocity gradient for linear hats, apic_dinv = 0), the
    divergences of the water's and the solid's velocities at the particle and the node fill interpolated
    (at the particles' positions before they move).  With FLIP (``flip`` the ratio > 0, the solid's) the
    water's velocity is flip (v_wp + sum N (v_wI - v_wI,old)) + (1 - flip) sum N v_wI."""
    S = len(tag)
    d = p_x.shape[1]
    inv_h = 1.0 / h
    Sz = S if d == 3 else 1
    b, wx, dx, wy, dy, wz, dz = particle_stencil(p_x, p, origin, kind, inv_h, d)
    v0 = v1 = v2 = div = divs = fill = 0.0
    q0 = q1 = q2 = 0.0  # sum N v_wI,old (FLIP)
    # A[a, e] = sum v_a (x_I - x_p)_e (APIC) or sum v_a dN/dx_e (linear hats)
    a00 = a01 = a02 = a10 = a11 = a12 = a20 = a21 = a22 = 0.0
    o0 = b[0] * h + origin[0] - p_x[p, 0]
    o1 = b[1] * h + origin[1] - p_x[p, 1]
    o2 = b[2] * h + origin[2] - p_x[p, 2] if d == 3 else 0.0
    # the affine sums without a branch per node: e = apic wt (x_I - x_p) + grad grad N
    apic = 1.0 if affine and apic_dinv > 0.0 else 0.0
    grad = 1.0 if affine and apic_dinv <= 0.0 else 0.0
    for i in range(S):
        ex = apic * (o0 + i * h)
        for j in range(S):
            ey = apic * (o1 + j * h)
            wij = wx[i] * wy[j]
            dxj = dx[i] * wy[j]
            dyj = wx[i] * dy[j]
            for k in range(Sz):
                wt = wij * wz[k]
                idx = node_index(b, lo, nloc, i, j, k, d)
                gx = dxj * wz[k]
                gy = dyj * wz[k]
                gz = wij * dz[k] if d == 3 else 0.0
                u0 = g_vw[idx, 0]
                u1 = g_vw[idx, 1]
                u2 = g_vw[idx, 2] if d == 3 else 0.0
                v0 += wt * u0
                v1 += wt * u1
                v2 += wt * u2
                q0 += wt * g_vwold[idx, 0]
                q1 += wt * g_vwold[idx, 1]
                if d == 3:
                    q2 += wt * g_vwold[idx, 2]
                div += gx * u0 + gy * u1 + gz * u2
                divs += gx * g_vs[idx, 0] + gy * g_vs[idx, 1]
                if d == 3:
                    divs += gz * g_vs[idx, 2]
                fill += wt * g_fill[idx]
                e0 = wt * ex + grad * gx
                e1 = wt * ey + grad * gy
                e2 = wt * apic * (o2 + k * h) + grad * gz
                a00 += u0 * e0
                a01 += u0 * e1
                a02 += u0 * e2
                a10 += u1 * e0
                a11 += u1 * e1
                a12 += u1 * e2
                a20 += u2 * e0
                a21 += u2 * e1
                a22 += u2 * e2
    keep = 1.0 - flip
    p_vw[p, 0] = flip * (p_vw[p, 0] + v0 - q0) + keep * v0
    p_vw[p, 1] = flip * (p_vw[p, 1] + v1 - q1) + keep * v1
    if d == 3:
        p_vw[p, 2] = flip * (p_vw[p, 2] + v2 - q2) + keep * v2
    if affine:
        f = apic_dinv if apic_dinv > 0.0 else 1.0
        p_Cw[p, 0, 0], p_Cw[p, 0, 1], p_Cw[p, 1, 0], p_Cw[p, 1, 1] = f * a00, f * a01, f * a10, f * a11
        if d == 3:
            p_Cw[p, 0, 2], p_Cw[p, 1, 2] = f * a02, f * a12
            p_Cw[p, 2, 0], p_Cw[p, 2, 1], p_Cw[p, 2, 2] = f * a20, f * a21, f * a22
    p_divw[p] = div
    p_divs[p] = divs
    p_fill[p] = fill


@njit(cache=True, inline="always")
def drained(row, sat, n, fill):
    """A particle without pore pressure: dry, separated or drained (at the free surface or a drained wall:
    its node fill below FREE_SURFACE_FILL)."""
    return wet(row, sat, n) == 0.0 or fill < FREE_SURFACE_FILL


@njit(cache=True, inline="always")
def porosity_one(p, p_n, p_vol, p_vol0, p_material, table):
    """n = 1 - (1 - n0) V0 / V from particle p's skeleton volume after the step."""
    row = table[p_material[p]]
    if row[WATER.n0] > 0.0:
        p_n[p] = max(1.0 - (1.0 - row[WATER.n0]) * p_vol0[p] / p_vol[p], 1e-6)


@njit(cache=True, inline="always")
def speed_terms_one(p, p_v, p_vw, p_n, p_rho, p_sat, row):
    """Particle p's terms of the stable step: (its porosity where it holds water, else 1; its dry density;
    its saturated density; the larger squared speed of its two phases)."""
    d = p_v.shape[1]
    s = wet(row, p_sat[p], p_n[p])
    vs = 0.0
    vw = 0.0
    for a in range(d):
        vs += p_v[p, a] * p_v[p, a]
        vw += p_vw[p, a] * p_vw[p, a]
    return p_n[p] if s > 0.0 else 1.0, p_rho[p], p_rho[p] + s * p_n[p] * row[WATER.rho_w], max(vs, vw)


@njit(cache=True, inline="always")
def flag_drained_one(p, p_fill, p_sat, p_n, p_material, table, p_drained):
    """p_drained[p] = 1 where particle p holds no pore pressure (``drained``), 0 where it holds one."""
    p_drained[p] = 1.0 if drained(table[p_material[p]], p_sat[p], p_n[p], p_fill[p]) else 0.0


@njit(cache=True, inline="always")
def smooth_node_one(i, g_vp, g_p):
    """Node i of the smoothing S: f_I = sum N V f / sum N V (g_vp: the scatter's sums, halo summed)."""
    g_p[i] = g_vp[i, 1] / g_vp[i, 0] if g_vp[i, 0] > 0.0 else 0.0


@njit(cache=True, inline="always")
def smooth_gather_one(p, tag, p_x, p_drained, g_p, origin, h, kind, lo, nloc, p_out):
    """p_out[p] = sum_I N_I g_p[I] (0 where particle p is drained): the gather of the smoothing S (after
    smooth_node_one)."""
    if p_drained[p] != 0.0:
        p_out[p] = 0.0
        return
    S = len(tag)
    d = p_x.shape[1]
    Sz = S if d == 3 else 1
    b, wx, dx, wy, dy, wz, dz = particle_stencil(p_x, p, origin, kind, 1.0 / h, d)
    s = 0.0
    for i in range(S):
        for j in range(S):
            wij = wx[i] * wy[j]
            for k in range(Sz):
                s += wij * wz[k] * g_p[node_index(b, lo, nloc, i, j, k, d)]
    p_out[p] = s


@njit(cache=True, inline="always")
def pressure_increment_one(p, p_dp, p_divw, p_divs, p_n, p_material, table, dt):
    """Particle p: the water's mass balance, dp = -dt K_w / n [(1 - n) div v_s + n div v_w], before it moves."""
    row = table[p_material[p]]
    n = p_n[p]
    p_dp[p] = -dt * row[WATER.k_w] / n * ((1.0 - n) * p_divs[p] + n * p_divw[p]) if n > 0.0 else 0.0


@njit(cache=True, inline="always")
def add_increment_one(p, p_carried, p_pore, p_dp, p_drained, p_material, table):
    """Both pressures of particle p += dp where it holds pressure, the acting one (p_pore) never below the
    water's cavitation pressure (cavitation_one); both 0 where it is drained.  The carried pressure is the
    water's mass balance unbounded: below p_cav it measures the vapour the pores hold, (p_cav - p) n / K_w of
    their volume, which a recompression closes before the acting pressure rises again."""
    if p_drained[p] != 0.0:
        p_carried[p] = 0.0
        p_pore[p] = 0.0
    else:
        p_carried[p] += p_dp[p]
        p_pore[p] = max(p_pore[p] + p_dp[p], table[p_material[p], WATER.p_cav])


@njit(cache=True, inline="always")
def acting_one(p, p_pore, p_carried, p_drained, p_material, table):
    """Particle p's acting pressure from its carried one where the pressure is not seen through the grid
    (solver.pore_pressure_smoothing false): p_carried, held at p_cav (cavitation_one); 0 where drained."""
    p_pore[p] = 0.0 if p_drained[p] != 0.0 else max(p_carried[p], table[p_material[p], WATER.p_cav])


@njit(cache=True, inline="always")
def cavitation_one(p, p_pore, p_material, table):
    """The acting pressure of particle p held at the water's cavitation pressure p_cav <= 0: the water
    vaporises below it (docs/pore-water.md, Suction).  With the carried pressure unbounded the hold is a
    reversible, bilinear law of the water, p = max(p*, p_cav) with p* the mass balance's pressure: vapour forms
    as the pores dilate and closes as they contract, so the pressure's work stays a function of the state and
    the health check's energy budget needs no term for it."""
    p_pore[p] = max(p_pore[p], table[p_material[p], WATER.p_cav])


@njit(cache=True, inline="always")
def fold_one(i, g_image, rows):
    """Node i of a periodic grid: where it is a ghost (g_image[i] >= 0, the window index of its image) the
    ghost's and the image's partial sums are added and both take the total, so every periodic copy of a
    node holds the whole node (``rows``: (nn, width) sums of a scatter; a ghost has one image, an image one
    ghost: the pairs are disjoint)."""
    j = g_image[i]
    if j < 0:
        return
    for a in range(rows.shape[1]):
        t = rows[i, a] + rows[j, a]
        rows[i, a] = t
        rows[j, a] = t
