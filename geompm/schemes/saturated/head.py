"""A wall that holds a head: groundwater fed through a face of the grid at a level H [m] (constant or in time).

The pore pressure at the face is p_h = rho_w |g| (H - z) (0 above the level).  It enters the two-phase step
as a Dirichlet condition on the pressure, written so that it is exact at hydrostatic rest on the discrete grid:
with a reference field p_ref = p_h(z) phi(d) that equals p_h within one cell of the face (d < h, d the
distance into the soil) and falls linearly to 0 over the next ``BAND`` cells, the water's weak form

    F_I = sum V n p grad N_I  -  sum over the band of V n [p_ref grad N_I + N_I grad p_ref]

is that of the excess p - p_ref, which vanishes on the face, plus the volume force -n grad p_ref: the face's
boundary term -oint N p_h n_out dA without a surface integral (divergence theorem; p_ref = 0 where the band
ends, so no other boundary sees it).  The particles within one cell of the face hold p = p_h(z) (marked
drained while the increments are smoothed, so the water they give is not spread onto their neighbours, then
held); the face's nodes let the water cross as a drained wall's do, the face counted as filled (no free
surface).  At rest at H equal to the soil's top, the band's force cancels the held particles' own
contribution and the column stays hydrostatic; with H above it the water flows in by Darcy's law (docs/pore-
water.md, Water from a boundary).
"""

from numba import njit

from geompm.schemes.saturated.kernels import FORCE, WALL, WATER, node_index, particle_stencil, wet

#: cells over which the reference field falls from p_h to 0 beyond the held layer
BAND = 2.0


@njit(cache=True, inline="always")
def _reference(x0, x1, x2, d, walls, k, level, rho_w, gravity, g, h):
    """(p_ref, its gradient (3), the distance d into the soil) at a point for wall row k with level H."""
    dist = (x0 - walls[k, WALL.px]) * walls[k, WALL.nx] + (x1 - walls[k, WALL.py]) * walls[k, WALL.ny]
    gx = x0 * gravity[0] + x1 * gravity[1]
    if d == 3:
        dist += (x2 - walls[k, WALL.pz]) * walls[k, WALL.nz]
        gx += x2 * gravity[2]
    ph = rho_w * (g * level + gx)
    if ph <= 0.0 or dist >= (1.0 + BAND) * h:
        return 0.0, 0.0, 0.0, 0.0, dist
    phi, slope = 1.0, 0.0
    if dist > h:
        phi = 1.0 - (dist - h) / (BAND * h)
        slope = -1.0 / (BAND * h)
    return (ph * phi, phi * rho_w * gravity[0] + ph * slope * walls[k, WALL.nx],
            phi * rho_w * gravity[1] + ph * slope * walls[k, WALL.ny],
            phi * rho_w * (gravity[2] if d == 3 else 0.0) + ph * slope * walls[k, WALL.nz], dist)


@njit(cache=True, inline="always")
def head_one(p, p_x, p_drained, p_carried, p_pore, p_sat, p_n, p_material, table, walls, heads, gravity, g, h,
             hold):
    """Particle p, saturated, within one cell of a wall that holds a head (heads[k] the level H [m], NaN for a
    wall without one): with ``hold`` 0 marked drained (before the increments are smoothed); with ``hold`` 1
    both its pressures held at p_h = rho_w |g| (H - z) and it holds pressure (p_drained 0)."""
    row = table[p_material[p]]
    if wet(row, p_sat[p], p_n[p]) == 0.0:
        return
    d = p_x.shape[1]
    x2 = p_x[p, 2] if d == 3 else 0.0
    for k in range(walls.shape[0]):
        if heads[k] != heads[k]:
            continue
        ref, _, _, _, dist = _reference(p_x[p, 0], p_x[p, 1], x2, d, walls, k, heads[k], row[WATER.rho_w], gravity,
                                        g, h)
        if dist < h:
            if hold == 0:
                p_drained[p] = 1.0
            else:
                p_carried[p] = ref
                p_pore[p] = ref
                p_drained[p] = 0.0
            return


@njit(cache=True)
def band_force(tag, p_x, p_vol, p_n, p_sat, p_material, table, walls, heads, gravity, g, h, origin, kind, lo,
               nloc, g_w):
    """g_w FORCE -= sum over the particles in a held head's band of V s n [p_ref grad N + N grad p_ref]
    (module docstring); serial: the band is a few cells of particles."""
    d = p_x.shape[1]
    S = len(tag)
    Sz = S if d == 3 else 1
    inv_h = 1.0 / h
    for p in range(p_x.shape[0]):
        row = table[p_material[p]]
        s = wet(row, p_sat[p], p_n[p])
        if s == 0.0:
            continue
        x2 = p_x[p, 2] if d == 3 else 0.0
        for k in range(walls.shape[0]):
            if heads[k] != heads[k]:
                continue
            ref, r0, r1, r2, dist = _reference(p_x[p, 0], p_x[p, 1], x2, d, walls, k, heads[k], row[WATER.rho_w],
                                               gravity, g, h)
            if ref == 0.0 and r0 == 0.0 and r1 == 0.0 and r2 == 0.0:
                continue
            c = p_vol[p] * s * p_n[p]
            b, wx, dx, wy, dy, wz, dz = particle_stencil(p_x, p, origin, kind, inv_h, d)
            for i in range(S):
                for j in range(S):
                    for m in range(Sz):
                        N = wx[i] * wy[j] * wz[m]
                        I = node_index(b, lo, nloc, i, j, m, d)
                        g_w[I, FORCE] -= c * (ref * dx[i] * wy[j] * wz[m] + N * r0)
                        g_w[I, FORCE + 1] -= c * (ref * wx[i] * dy[j] * wz[m] + N * r1)
                        if d == 3:
                            g_w[I, FORCE + 2] -= c * (ref * wx[i] * wy[j] * dz[m] + N * r2)
