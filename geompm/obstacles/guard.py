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

from .contact_force import COUNT, DEPTH, OBSTACLE, contact_and_record
from .sdf_field import interp_field

GUARD_REFINE = 4  # lattice spacing at most h / GUARD_REFINE
MIN_STEP = 0.25  # marching step at least MIN_STEP * hs
BISECTIONS = 30
O = OBSTACLE


@njit(cache=True)  # a call, not inlined: five uses in guard_rule would make its loops slow to compile
def _phi(field, prm, x, base, frac, val):
    d = x.shape[0]
    interp_field(field, prm[O.lat_x:O.lat_x + d], 1.0 / prm[O.spacing], prm[O.shape_x:O.shape_x + d], x, base,
                 frac, val)
    return val[0]


@njit(cache=True, inline="always")
def _inside_lattice(x, prm):
    for a in range(x.shape[0]):
        lo = prm[O.lat_x + a]
        if x[a] < lo or x[a] > lo + (prm[O.shape_x + a] - 1.0) * prm[O.spacing]:
            return False
    return True


@njit(cache=True, inline="always")
def guard_rule(prm, field, dt, k, p_x, x0, p_v, C, m, s, work, out):
    """Put back the particle if it is inside or went through the obstacle; ``field`` the guard lattice
    (points, 1 + d); out as in base.obstacle_node_rule, plus out[COUNT] (corrections) and out[DEPTH]
    (the largest depth [m] found before correction)."""
    d = p_x.shape[0]
    hs = prm[O.spacing]
    for a in range(d):  # most particles leave here, before any view is made
        lo = prm[O.lat_x + a]
        xa = p_x[a] - prm[O.shift_x + a]
        if xa < lo or xa > lo + (prm[O.shape_x + a] - 1.0) * hs:
            return
    x = work[0:d]
    xo = work[d:2 * d]
    y = work[2 * d:3 * d]
    f = work[3 * d:4 * d]
    normal = work[4 * d:5 * d]
    base = work[5 * d:6 * d]
    frac = work[6 * d:7 * d]
    val = work[7 * d:8 * d + 1]
    shift = prm[O.shift_x:O.shift_x + d]
    for a in range(d):
        x[a] = p_x[a] - shift[a]
        xo[a] = x[a] - dt * p_v[a]
    phi = _phi(field, prm, x, base, frac, val)
    hit = False
    if phi < 0.0:
        hit = True
        out[DEPTH] = max(out[DEPTH], -phi)
        for _ in range(2):  # project onto phi = 0 along the gradient
            g2 = 0.0
            for a in range(d):
                g2 += val[1 + a] * val[1 + a]
            if g2 == 0.0:
                break
            for a in range(d):
                x[a] -= phi * val[1 + a] / g2
            phi = _phi(field, prm, x, base, frac, val)
    elif _inside_lattice(xo, prm):
        seg = 0.0
        for a in range(d):
            seg += (x[a] - xo[a]) ** 2
        seg = np.sqrt(seg)
        phi0 = _phi(field, prm, xo, base, frac, val)
        if seg > 0.0 and -hs < phi0 < seg:  # a start on the surface (phi0 ~ 0) is marched too
            t_out, t = 0.0, 0.0
            cur = max(phi0, 0.0)
            while t < 1.0:
                t_out = t
                t = min(1.0, t + max(cur, MIN_STEP * hs) / seg)
                for a in range(d):
                    y[a] = xo[a] + t * (x[a] - xo[a])
                cur = _phi(field, prm, y, base, frac, val)
                if cur < 0.0:
                    hit = True
                    break
            if hit:
                t_in = t
                for _ in range(BISECTIONS):
                    tm = 0.5 * (t_out + t_in)
                    for a in range(d):
                        y[a] = xo[a] + tm * (x[a] - xo[a])
                    if _phi(field, prm, y, base, frac, val) < 0.0:
                        t_in = tm
                    else:
                        t_out = tm
                for a in range(d):
                    x[a] = xo[a] + t_out * (x[a] - xo[a])
                _phi(field, prm, x, base, frac, val)
    if not hit:
        return
    for a in range(d):
        normal[a] = val[1 + a]
        p_x[a] = x[a] + shift[a]
    if contact_and_record(p_v, normal, prm[O.vel_x:O.vel_x + d], int(prm[O.condition]), prm[O.mu], m, 1.0 / dt,
                          x, shift, prm[O.moment_x:O.moment_x + d], y, f, out):
        out[COUNT] += 1.0


def guard_spacing(h: float, thinnest: float | None) -> float:
    """Lattice spacing of the guard: h / GUARD_REFINE, finer if the obstacle's thinnest part needs it."""
    hs = h / GUARD_REFINE
    if thinnest is not None and thinnest > 0.0:
        hs = min(hs, thinnest / 3.0)
    return hs


def lattice_points(lo, hi, hs, pad) -> int:
    return int(np.prod(np.ceil((np.asarray(hi) - np.asarray(lo) + 2 * pad) / hs) + 1))
