"""The contact rule on one velocity against a rigid obstacle, and the force that it records.

Shared by the grid contact on nodes (base.obstacle_node_rule) and the particle
guard (guard.guard_rule): the velocity relative to the obstacle gets
the rule of contact/rules.py along the unit normal n = grad(phi)/|grad(phi)|,
and the momentum that removed, f = -m (v_after - v_before) / dt, is added to
the obstacle's ``out``: f (0:d), its normal part f_n = -f . n (d; pushing into
the obstacle is positive), f_n n (d+1:2d+1), and the moment (x - moment_point) x f
(2d+1:2d+4; only the z component in 2D).
"""

from __future__ import annotations

import math

from numba import njit

from geompm.contact.rules import apply_condition, effective_mu
from geompm.contact.voellmy import VOELLMY, turbulent_drag
from geompm.contract.layout import param_layout
from geompm.contact.sdf_field import nearest_point

#: an obstacle's packed parameters (3 slots per vector, 2D uses two): its signed-distance lattice (first
#: point [m], points per axis, spacing [m]), its displacement at the pass's time [m], its velocity [m/s],
#: the moment's reference point [m], the contact layer [m], the condition (contact/rules.py) and
#: the Coulomb coefficient [-]; Voellmy's xi [m/s2], rho g h^(d-1) of its drag and the lowest signed
#: distance of the nodes that take it [m] (contact/voellmy.py; the terrain offers it)
OBSTACLE = param_layout("lat_x", "lat_y", "lat_z", "shape_x", "shape_y", "shape_z", "spacing",
                        "shift_x", "shift_y", "shift_z", "vel_x", "vel_y", "vel_z",
                        "moment_x", "moment_y", "moment_z", "layer", "condition", "mu", "xi", "drag", "band")
FORCE_SLOTS = 10  # out[0:2d+4] (below) for d <= 3
COUNT, DEPTH = FORCE_SLOTS, FORCE_SLOTS + 1  # the guard's corrections and its deepest penetration [m]
#: where the per-face forces start in the grid pass's and the guard's rows: (faces, d) after the totals
FACES_GRID, FACES_GUARD = FORCE_SLOTS, DEPTH + 1


@njit(cache=True, inline="always")
def contact_and_record(v, w, n0, x0, b0, f0, prm, m, inv_dt, pw, wet, out, phi):
    """Apply the rule to the velocity v (d,), with w[n0:n0 + d] holding grad(phi) (normalised here, in
    place), and record the force.  With ``wet`` the friction acts on the effective normal force of the
    node's pore water ``pw`` (contact/rules.effective_mu); the particle guard passes False (a particle
    carries no nodal pore water: its correction takes the total).

    ``w[x0:x0 + d]`` is the point in the obstacle's frame; its displacement
    prm[shift], so x + shift is where the force acts; w[b0:...], w[f0:...] are
    scratch.  The obstacle's velocity, moment point, condition and
    coefficient come from ``prm`` (OBSTACLE layout); vectors are read at
    offsets, never sliced (contact.apply_condition).  With the condition 'voellmy' a node whose signed
    distance ``phi`` is above prm[band] (the bed's first layer) also takes the turbulent drag, recorded
    with the rest (contact/voellmy.py; the particle guard passes -inf).  Returns False, and
    changes nothing, if the gradient is zero."""
    d = v.shape[0]
    vel0, shift0, mom0 = OBSTACLE.vel_x, OBSTACLE.shift_x, OBSTACLE.moment_x
    norm = 0.0
    for a in range(d):
        norm += w[n0 + a] * w[n0 + a]
    if norm == 0.0:
        return False
    norm = math.sqrt(norm)
    for a in range(d):
        w[n0 + a] /= norm
        w[b0 + a] = v[a]
        v[a] -= prm[vel0 + a]
    mu = effective_mu(prm[OBSTACLE.mu], pw, w, n0, d) if wet else prm[OBSTACLE.mu]
    condition = int(prm[OBSTACLE.condition])
    apply_condition(v, w, n0, condition, mu)
    if condition == VOELLMY and phi > prm[OBSTACLE.band]:
        turbulent_drag(v, w, n0, prm[OBSTACLE.drag], prm[OBSTACLE.xi], 1.0 / inv_dt, m)
    fn = 0.0
    for a in range(d):
        v[a] += prm[vel0 + a]
        w[f0 + a] = -m * (v[a] - w[b0 + a]) * inv_dt  # force on the obstacle
        out[a] += w[f0 + a]
        fn -= w[f0 + a] * w[n0 + a]  # normal points out of the obstacle: pushing in is positive
    out[d] += fn
    for a in range(d):
        out[d + 1 + a] -= fn * w[n0 + a]
    r0 = w[x0] + prm[shift0] - prm[mom0]
    r1 = w[x0 + 1] + prm[shift0 + 1] - prm[mom0 + 1]
    f_0, f_1 = w[f0], w[f0 + 1]
    if d == 3:
        r2 = w[x0 + 2] + prm[shift0 + 2] - prm[mom0 + 2]
        f_2 = w[f0 + 2]
        out[2 * d + 1] += r1 * f_2 - r2 * f_1
        out[2 * d + 2] += r2 * f_0 - r0 * f_2
        out[2 * d + 3] += r0 * f_1 - r1 * f_0
    else:
        out[2 * d + 3] += r0 * f_1 - r1 * f_0
    return True


@njit(cache=True, inline="always")
def record_on_face(field, prm, w, base0, frac0, f0, d, slot0, out):
    """Share the force w[f0:f0 + d] among the faces of the lattice point nearest to the last interpolation
    (interp_field's base and fraction in w): out[slot0 + face d + a].  Nothing without face columns
    (the surfaces writer is off) or where the point has none (-1)."""
    k = field.shape[1] - d - 1  # the samples of sdf_field.face_lattice_ids, each with an equal share
    if k <= 0:
        return
    row = nearest_point(prm, OBSTACLE.shape_x, w, base0, frac0, d)
    for c in range(k):
        face = int(field[row, d + 1 + c])
        if face < 0:
            return
        for a in range(d):
            out[slot0 + face * d + a] += w[f0 + a] / k
