"""The velocity behind an impermeable wall or plane: the material's normal velocity mirrored onto the nodes
beyond it (docs/pore-water.md, Walls and the bottom row).

A quadratic or cubic B-spline reaches nodes behind a wall (signed distance < 0).  The wall's rule
(contact/rules.py) removes their velocity into the wall, so a layer that thins towards the wall (the
material above moving towards it, v_n(h) < 0) leaves those nodes at v_n = 0: the particles of the bottom row
then see dv_n/dn about 3/4 of the material's (quadratic B-splines, a particle a quarter cell above the wall),
a spurious dilation of the bottom row that the water resists with suction.  Measured on a saturated
Drucker-Prager block sliding down a bed aligned with the grid (h = 0.05 m, 0.4 s): the bottom row's pore
pressure 171-468 Pa against 700-955 Pa in the row above it (explicit step), -807 to 301 Pa under the
semi-implicit step, and the basal friction it sets (benchmarks/results/2026-12-05-issue53/bottom_row/).

The continuum's velocity is antisymmetric in its normal component about a wall the material presses on
(the image of the flow in the wall: the wall's plane has v_n = 0 and dv_n/dn continuous), so a node at
signed distance -d takes v_n = -v_n(y) at its mirror point y = x + 2 d n, when the material there moves
towards the wall (v_n(y) < 0); a material that moves away (lift-off, expansion) keeps the wall's rule.
v(y) is the mass-weighted multilinear interpolation of the nodes around y after the stages (a node itself
for a wall on a grid face).  The tangential part is the wall's (slip, friction).  A drained wall keeps its
rule (the water crosses it).  A fixed impermeable rigid solid (an obstacle, analytic or STL, or the terrain)
is mirrored the same way through its own surface: a node at depth d inside it (solids.py, the row's depth
and the normal out of the solid) takes v_n = -v_n(x + 2 d n); a moving solid and a drained one keep their
rule.
"""

from numba import njit

from geompm.schemes.saturated.kernels import WALL, node_of

#: a node closer than this fraction of h to a wall's plane is on it (contact.rules.ON_SURFACE), not behind it
BEHIND = 1e-9


@njit(cache=True, inline="always")
def node_copy_one(i, src, dst):
    """dst[i] <- src[i] (the velocities the mirror reads, before it writes)."""
    for a in range(src.shape[1]):
        dst[i, a] = src[i, a]


@njit(cache=True)
def velocity_at(y0, y1, y2, g_snap, g_mass, origin, h, lo, nloc, d, mass_eps, a0, a1, a2):
    """The component of the velocity along (a0, a1, a2) at the point y: multilinear over the nodes of y's
    cell that carry mass, weights renormalised; (0, 0) when none does or the cell leaves the window; the
    second value is the weight found."""
    f0 = (y0 - origin[0]) / h
    f1 = (y1 - origin[1]) / h
    f2 = (y2 - origin[2]) / h if d == 3 else 0.0
    b0 = int(f0 + 1e-9) if f0 >= 0.0 else int(f0 + 1e-9) - 1
    b1 = int(f1 + 1e-9) if f1 >= 0.0 else int(f1 + 1e-9) - 1
    b2 = (int(f2 + 1e-9) if f2 >= 0.0 else int(f2 + 1e-9) - 1) if d == 3 else 0
    r0 = min(max(f0 - b0, 0.0), 1.0)
    r1 = min(max(f1 - b1, 0.0), 1.0)
    r2 = min(max(f2 - b2, 0.0), 1.0)
    total = 0.0
    value = 0.0
    for c0 in range(2):
        w0 = r0 if c0 == 1 else 1.0 - r0
        i0 = b0 + c0 - lo[0]
        if w0 <= 0.0 or i0 < 0 or i0 >= nloc[0]:
            continue
        for c1 in range(2):
            w1 = r1 if c1 == 1 else 1.0 - r1
            i1 = b1 + c1 - lo[1]
            if w1 <= 0.0 or i1 < 0 or i1 >= nloc[1]:
                continue
            for c2 in range(2 if d == 3 else 1):
                w2 = (r2 if c2 == 1 else 1.0 - r2) if d == 3 else 1.0
                idx = i0 * nloc[1] + i1
                if d == 3:
                    i2 = b2 + c2 - lo[2]
                    if w2 <= 0.0 or i2 < 0 or i2 >= nloc[2]:
                        continue
                    idx = idx * nloc[2] + i2
                if g_mass[idx] <= mass_eps:
                    continue
                w = w0 * w1 * w2
                vn = g_snap[idx, 0] * a0 + g_snap[idx, 1] * a1
                if d == 3:
                    vn += g_snap[idx, 2] * a2
                total += w
                value += w * vn
    if total <= 0.0:
        return 0.0, 0.0
    return value / total, total


@njit(cache=True, inline="always")
def mirror_normal(i, x0, x1, x2, dist, n0, n1, n2, g_snap, g_mass, origin, h, lo, nloc, mass_eps, g_vel):
    """Node i at signed distance dist < 0 from a surface with unit normal n (into the material): its normal
    velocity set to -v_n at its mirror point where the material there moves towards the surface."""
    d = g_vel.shape[1]
    vn_image, weight = velocity_at(x0 - 2.0 * dist * n0, x1 - 2.0 * dist * n1, x2 - 2.0 * dist * n2, g_snap,
                                   g_mass, origin, h, lo, nloc, d, mass_eps, n0, n1, n2)
    if weight <= 0.0 or vn_image >= 0.0:
        return
    vn = g_vel[i, 0] * n0 + g_vel[i, 1] * n1
    if d == 3:
        vn += g_vel[i, 2] * n2
    dv = -vn_image - vn
    g_vel[i, 0] += dv * n0
    g_vel[i, 1] += dv * n1
    if d == 3:
        g_vel[i, 2] += dv * n2


@njit(cache=True, inline="always")
def node_mirror_one(i, g_snap, g_mass, walls, g_solid, origin, h, lo, nloc, mass_eps, g_vel):
    """Node i behind an impermeable wall k (signed distance below -BEHIND h) or inside a fixed impermeable
    solid (g_solid[i, 5] its depth above BEHIND h, g_solid[i, 2:5] the normal out of it) whose mirror point's
    material moves towards the surface: v_n <- -v_n(mirror) (module docstring)."""
    if g_mass[i] <= mass_eps:
        return
    d = g_vel.shape[1]
    ix, iy, iz = node_of(i, lo, nloc, d)
    x0 = origin[0] + ix * h
    x1 = origin[1] + iy * h
    x2 = origin[2] + iz * h if d == 3 else 0.0
    if g_solid[i, 5] > BEHIND * h:
        mirror_normal(i, x0, x1, x2, -g_solid[i, 5], g_solid[i, 2], g_solid[i, 3], g_solid[i, 4], g_snap, g_mass,
                      origin, h, lo, nloc, mass_eps, g_vel)
    for k in range(walls.shape[0]):
        if walls[k, WALL.drained] > 0.0:
            continue
        n0, n1, n2 = walls[k, WALL.nx], walls[k, WALL.ny], walls[k, WALL.nz]
        dist = (x0 - walls[k, WALL.px]) * n0 + (x1 - walls[k, WALL.py]) * n1
        if d == 3:
            dist += (x2 - walls[k, WALL.pz]) * n2
        if dist < -BEHIND * h:
            mirror_normal(i, x0, x1, x2, dist, n0, n1, n2, g_snap, g_mass, origin, h, lo, nloc, mass_eps, g_vel)
