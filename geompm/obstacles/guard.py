"""Particle-level penetration guard of rigid obstacles: nothing passes, nothing ends a step inside.

Grid contact (base.py) acts on nodes whose signed distance is <= 0.  An
obstacle thinner than about two cells can fall between the nodes: no node is
inside, no node is in contact, and debris flows through it (issue 15: the
check dam at h = 0.07 m took 0.9 N instead of ~500 N).  After G2P every
particle is therefore checked against a finer signed-distance lattice of the
obstacle (spacing ``hs`` <= h / 4 and <= a third of the obstacle's thinnest
part):

1. its end-of-step position x: if phi(x) < 0 it has penetrated; it is put
   back on the surface, x <- x - phi(x) n (two projection steps), n the unit
   gradient of phi;
2. otherwise the segment it travelled this step, from x - dt v to x, is
   marched in steps of max(phi, hs / 4): the distance to the surface, but
   never less than hs / 4; if phi < 0 anywhere on
   it the particle crossed a thin part within the step, and it is put on the
   entry side's surface point, found by bisection.

A particle that was put back gets the contact rule on its velocity relative
to the obstacle and adds the momentum that removed to the obstacle's force,
normal force and moment (contact_force.py, the same code as the grid
contact), so the force history holds every correction.  The segment start x - dt v is the exact start of the step for
PIC, APIC and MLS under USL (the particle moves with its new velocity); for
FLIP and MUSL it is an approximation of the path (the end-point test is exact
for every scheme).  The lattice covers the obstacle's bounds plus h + 2 hs, so
any segment that can reach the obstacle (|v| dt <= cfl h < h) lies inside it.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .contact_force import contact_and_record
from .sdf_field import interp_field

GUARD_REFINE = 4  # lattice spacing at most h / GUARD_REFINE
MIN_STEP = 0.25  # marching step at least MIN_STEP * hs
BISECTIONS = 30


@njit(cache=True, inline="always")
def _phi(field, lat_origin, inv_hs, lat_shape, x, base, frac, val):
    interp_field(field, lat_origin, inv_hs, lat_shape, x, base, frac, val)
    return val[0]


@njit(cache=True, inline="always")
def _inside_lattice(x, lo, hi):
    for a in range(x.shape[0]):
        if x[a] < lo[a] or x[a] > hi[a]:
            return False
    return True


@njit(cache=True)
def guard_particles(p_x, p_v, p_mass, dt, field, lat_origin, hs, lat_shape, shift, vel, condition, mu,
                    moment_point, out):
    """Put back every particle inside or through the obstacle; out as in base.obstacle_apply, plus
    out[2d+4] = particles corrected.  Returns the largest depth [m] found before correction."""
    n, d = p_x.shape
    k = out.shape[0]
    inv_hs = 1.0 / hs
    inv_dt = 1.0 / dt
    lo = np.empty(d)
    hi = np.empty(d)
    for a in range(d):
        lo[a] = lat_origin[a]
        hi[a] = lat_origin[a] + (lat_shape[a] - 1) * hs
    x = np.empty(d)
    xo = np.empty(d)
    y = np.empty(d)
    f = np.empty(d)
    normal = np.empty(d)
    base = np.empty(d, np.int64)
    frac = np.empty(d)
    val = np.empty(d + 1)
    acc = np.zeros(k + 1)  # out's entries, then the deepest penetration
    # serial: almost every particle leaves at the bounding-box test, and it compiles fast
    for p in range(n):
        for a in range(d):
            x[a] = p_x[p, a] - shift[a]
            xo[a] = x[a] - dt * p_v[p, a]
        if not _inside_lattice(x, lo, hi):
            continue
        phi = _phi(field, lat_origin, inv_hs, lat_shape, x, base, frac, val)
        hit = False
        if phi < 0.0:
            hit = True
            acc[k] = max(acc[k], -phi)
            for _ in range(2):  # project onto phi = 0 along the gradient
                g2 = 0.0
                for a in range(d):
                    g2 += val[1 + a] * val[1 + a]
                if g2 == 0.0:
                    break
                for a in range(d):
                    x[a] -= phi * val[1 + a] / g2
                phi = _phi(field, lat_origin, inv_hs, lat_shape, x, base, frac, val)
        elif _inside_lattice(xo, lo, hi):
            seg = 0.0
            for a in range(d):
                seg += (x[a] - xo[a]) ** 2
            seg = np.sqrt(seg)
            phi0 = _phi(field, lat_origin, inv_hs, lat_shape, xo, base, frac, val)
            if seg > 0.0 and -hs < phi0 < seg:  # a start on the surface (phi0 ~ 0) is marched too
                t_out, t = 0.0, 0.0
                cur = max(phi0, 0.0)
                while t < 1.0:
                    t_out = t
                    t = min(1.0, t + max(cur, MIN_STEP * hs) / seg)
                    for a in range(d):
                        y[a] = xo[a] + t * (x[a] - xo[a])
                    cur = _phi(field, lat_origin, inv_hs, lat_shape, y, base, frac, val)
                    if cur < 0.0:
                        hit = True
                        break
                if hit:
                    t_in = t
                    for _ in range(BISECTIONS):
                        tm = 0.5 * (t_out + t_in)
                        for a in range(d):
                            y[a] = xo[a] + tm * (x[a] - xo[a])
                        if _phi(field, lat_origin, inv_hs, lat_shape, y, base, frac, val) < 0.0:
                            t_in = tm
                        else:
                            t_out = tm
                    for a in range(d):
                        x[a] = xo[a] + t_out * (x[a] - xo[a])
                    _phi(field, lat_origin, inv_hs, lat_shape, x, base, frac, val)
        if not hit:
            continue
        for a in range(d):
            normal[a] = val[1 + a]
            p_x[p, a] = x[a] + shift[a]
        if not contact_and_record(p_v, p, normal, vel, condition, mu, p_mass[p], inv_dt, x, shift, moment_point,
                                  y, f, acc):
            continue
        acc[2 * d + 4] += 1.0
    for j in range(k):
        out[j] = acc[j]
    return acc[k]


def guard_spacing(h: float, thinnest: float | None) -> float:
    """Lattice spacing of the guard: h / GUARD_REFINE, finer if the obstacle's thinnest part needs it."""
    hs = h / GUARD_REFINE
    if thinnest is not None and thinnest > 0.0:
        hs = min(hs, thinnest / 3.0)
    return hs


def lattice_points(lo, hi, hs, pad) -> int:
    return int(np.prod(np.ceil((np.asarray(hi) - np.asarray(lo) + 2 * pad) / hs) + 1))
