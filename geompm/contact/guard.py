"""Particle-level penetration guard of rigid obstacles: nothing passes, nothing ends a step inside.

Grid contact (base.py) acts on nodes whose signed distance is <= 0.  An
obstacle thinner than about two cells can fall between the nodes: no node is
inside, no node is in contact, and debris flows through it (without
this guard, the check dam at h = 0.07 m took 0.9 N instead of ~500 N).  After G2P every
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
normal force and moment (contact/force.py, the same code as the grid
contact), so the force history holds every correction.  The segment start x - dt v is the exact start of the step for
PIC, APIC and MLS under USL (the particle moves with its new velocity); for
FLIP and MUSL it is an approximation of the path (the end-point test is exact
for every scheme).  The lattice covers the obstacle's bounds plus h + 2 hs, so
any segment that can reach the obstacle (|v| dt <= cfl h < h) lies inside it.
"""

from __future__ import annotations

import math

from numba import njit

from geompm.contact.force import COUNT, DEPTH, FACES_GUARD, OBSTACLE, contact_and_record, record_on_face
from geompm.contact.sdf_field import interp_field

GUARD_REFINE = 4  # lattice spacing at most h / GUARD_REFINE
MIN_STEP = 0.25  # marching step at least MIN_STEP * hs
BISECTIONS = 30
O = OBSTACLE


@njit(cache=True)  # a call, not inlined: five uses in guard_rule would make its loops slow to compile
def _phi(field, prm, w, x0, base0, frac0, val0, d):
    interp_field(field, prm, O.lat_x, O.shape_x, 1.0 / prm[O.spacing], w, x0, base0, frac0, val0, d)
    return w[val0]


@njit(cache=True, inline="always")
def _inside_lattice(w, x0, d, prm):
    for a in range(d):
        lo = prm[O.lat_x + a]
        if w[x0 + a] < lo or w[x0 + a] > lo + (prm[O.shape_x + a] - 1.0) * prm[O.spacing]:
            return False
    return True


@njit(cache=True, inline="always")
def guard_rule(prm, field, dt, k, p_x, x0, p_v, C, m, s, work, out):
    """Put back the particle if it is inside or went through the obstacle; ``field`` the guard lattice
    (points, 1 + d); out as in base.obstacle_node_rule, plus out[COUNT] (corrections) and out[DEPTH]
    (the largest depth [m] found before correction).  ``work`` holds at offsets of d (read at offsets,
    never sliced: contact.apply_condition) the end point x, the start xo, a point y on the segment, a
    force, the normal, the interpolation's base, fraction and d + 1 values."""
    d = p_x.shape[0]
    hs = prm[O.spacing]
    for a in range(d):  # most particles leave here
        lo = prm[O.lat_x + a]
        xa = p_x[a] - prm[O.shift_x + a]
        if xa < lo or xa > lo + (prm[O.shape_x + a] - 1.0) * hs:
            return
    x, xo, y, f, nrm, base, frac, val = 0, d, 2 * d, 3 * d, 4 * d, 5 * d, 6 * d, 7 * d
    w = work
    for a in range(d):
        w[x + a] = p_x[a] - prm[O.shift_x + a]
        w[xo + a] = w[x + a] - dt * p_v[a]
    phi = _phi(field, prm, w, x, base, frac, val, d)
    hit = False
    if phi < 0.0:
        hit = True
        out[DEPTH] = max(out[DEPTH], -phi)
        for _ in range(2):  # project onto phi = 0 along the gradient
            g2 = 0.0
            for a in range(d):
                g2 += w[val + 1 + a] * w[val + 1 + a]
            if g2 == 0.0:
                break
            for a in range(d):
                w[x + a] -= phi * w[val + 1 + a] / g2
            phi = _phi(field, prm, w, x, base, frac, val, d)
    elif _inside_lattice(w, xo, d, prm):
        seg = 0.0
        for a in range(d):
            seg += (w[x + a] - w[xo + a]) ** 2
        seg = math.sqrt(seg)
        phi0 = _phi(field, prm, w, xo, base, frac, val, d)
        if seg > 0.0 and -hs < phi0 < seg:  # a start on the surface (phi0 ~ 0) is marched too
            t_out, t = 0.0, 0.0
            cur = max(phi0, 0.0)
            while t < 1.0:
                t_out = t
                t = min(1.0, t + max(cur, MIN_STEP * hs) / seg)
                for a in range(d):
                    w[y + a] = w[xo + a] + t * (w[x + a] - w[xo + a])
                cur = _phi(field, prm, w, y, base, frac, val, d)
                if cur < 0.0:
                    hit = True
                    break
            if hit:
                t_in = t
                for _ in range(BISECTIONS):
                    tm = 0.5 * (t_out + t_in)
                    for a in range(d):
                        w[y + a] = w[xo + a] + tm * (w[x + a] - w[xo + a])
                    if _phi(field, prm, w, y, base, frac, val, d) < 0.0:
                        t_in = tm
                    else:
                        t_out = tm
                for a in range(d):
                    w[x + a] = w[xo + a] + t_out * (w[x + a] - w[xo + a])
                _phi(field, prm, w, x, base, frac, val, d)
    if not hit:
        return
    for a in range(d):
        w[nrm + a] = w[val + 1 + a]
        p_x[a] = w[x + a] + prm[O.shift_x + a]
    if contact_and_record(p_v, w, nrm, x, y, f, prm, m, 1.0 / dt, w, False, out, -math.inf):
        out[COUNT] += 1.0
        record_on_face(field, prm, w, base, frac, f, d, FACES_GUARD, out)


def guard_spacing(h: float, thinnest: float | None) -> float:
    """Lattice spacing of the guard: h / GUARD_REFINE, finer if the obstacle's thinnest part needs it."""
    hs = h / GUARD_REFINE
    if thinnest is not None and thinnest > 0.0:
        hs = min(hs, thinnest / 3.0)
    return hs

