"""The contact rule on one velocity against a rigid obstacle, and the force that it records.

Shared by the grid contact on nodes (base.obstacle_node_rule) and the particle
guard (guard.guard_rule): the velocity relative to the obstacle gets
the rule of boundaries/contact.py along the unit normal n = grad(phi)/|grad(phi)|,
and the momentum that removed, f = -m (v_after - v_before) / dt, is added to
the obstacle's ``out``: f (0:d), its normal part f_n = -f . n (d; pushing into
the obstacle is positive), f_n n (d+1:2d+1), and the moment (x - moment_point) x f
(2d+1:2d+4; only the z component in 2D).
"""

from __future__ import annotations

import math

from numba import njit

from ..boundaries.contact import apply_condition
from ..layout import param_layout

#: an obstacle's packed parameters (3 slots per vector, 2D uses two): its signed-distance lattice (first
#: point [m], points per axis, spacing [m]), its displacement at the pass's time [m], its velocity [m/s],
#: the moment's reference point [m], the contact layer [m], the condition (boundaries/contact.py) and
#: the Coulomb coefficient [-]
OBSTACLE = param_layout("lat_x", "lat_y", "lat_z", "shape_x", "shape_y", "shape_z", "spacing",
                        "shift_x", "shift_y", "shift_z", "vel_x", "vel_y", "vel_z",
                        "moment_x", "moment_y", "moment_z", "layer", "condition", "mu")
FORCE_SLOTS = 10  # out[0:2d+4] (below) for d <= 3
COUNT, DEPTH = FORCE_SLOTS, FORCE_SLOTS + 1  # the guard's corrections and its deepest penetration [m]


@njit(cache=True, inline="always")
def contact_and_record(v, normal, vel, condition, mu, m, inv_dt, x, shift, moment_point, before, f, out):
    """Apply the rule to the velocity v (d,) with ``normal`` holding grad(phi) (normalised here, in place).

    ``x`` is the point in the obstacle's frame, ``shift`` its displacement, so
    x + shift is where the force acts.  Returns False, and changes nothing, if
    the gradient is zero."""
    d = v.shape[0]
    norm = 0.0
    for a in range(d):
        norm += normal[a] * normal[a]
    if norm == 0.0:
        return False
    norm = math.sqrt(norm)
    for a in range(d):
        normal[a] /= norm
        before[a] = v[a]
        v[a] -= vel[a]
    apply_condition(v, normal, condition, mu)
    fn = 0.0
    for a in range(d):
        v[a] += vel[a]
        f[a] = -m * (v[a] - before[a]) * inv_dt  # force on the obstacle
        out[a] += f[a]
        fn -= f[a] * normal[a]  # normal points out of the obstacle: pushing in is positive
    out[d] += fn
    for a in range(d):
        out[d + 1 + a] -= fn * normal[a]
    r0 = x[0] + shift[0] - moment_point[0]
    r1 = x[1] + shift[1] - moment_point[1]
    if d == 3:
        r2 = x[2] + shift[2] - moment_point[2]
        out[2 * d + 1] += r1 * f[2] - r2 * f[1]
        out[2 * d + 2] += r2 * f[0] - r0 * f[2]
        out[2 * d + 3] += r0 * f[1] - r1 * f[0]
    else:
        out[2 * d + 3] += r0 * f[1] - r1 * f[0]
    return True
