"""What a step's end reduces per material block, in one row: the layout a device backend's step-end kernel
fills (backend/cuda_kernels.step_end) and the held step's check reads (engine/held_step.py), and the same
row computed on the host from the particle arrays (``end_rows``).

Row of END_ROW numbers per block: the minima of x per axis (negated, so that every bound is a maximum), the
maxima of x, the sums of x (a NaN or Inf anywhere shows in them), the largest |v| [m/s], the smallest density
(negated) and the largest [kg/m3], then the health sums (kernels/health.health_sums): particles with a
non-finite field, the kinetic energy [J] and the energy gravity released [J].  Three slots per axis whatever
the dimension; a plane-strain row leaves the third at its start.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

END_ROW = 15
#: the row's slots reduced as maxima (the others are sums)
END_MAXIMA = (0, 1, 2, 3, 4, 5, 9, 10, 11)
#: a row's starting values (the maxima at -inf, the sums at 0)
END_START = tuple(-math.inf if q in END_MAXIMA else 0.0 for q in range(END_ROW))
#: slot of the largest |v|, of the negated smallest density, of the largest density and of the non-finite count
SPEED, RHO_MIN, RHO_MAX, BAD = 9, 10, 11, 12


@njit(cache=True)
def particle_row(p, p_x, p_x0, p_v, p_rho, p_stress, p_mass, gravity, row):
    """Particle p's own END_ROW values written into ``row`` (at END_START): its coordinates where finite, its
    speed, density and health terms.  The device kernel (backend/cuda_kernels.step_end) and ``end_row`` combine
    the particles' rows, taking the maximum of the END_MAXIMA slots and the sum of the others."""
    d = p_x.shape[1]
    ok = True
    v2 = 0.0
    w = 0.0
    for a in range(d):
        x = p_x[p, a]
        if math.isfinite(x):
            row[a] = -x
            row[3 + a] = x
        else:
            ok = False
        row[6 + a] = x
        if not math.isfinite(p_v[p, a]):
            ok = False
        v2 += p_v[p, a] * p_v[p, a]
        w += gravity[a] * (x - p_x0[p, a])
    for k in range(6):
        if not math.isfinite(p_stress[p, k]):
            ok = False
    row[SPEED] = math.sqrt(v2)
    row[RHO_MIN] = -p_rho[p]
    row[RHO_MAX] = p_rho[p]
    if ok:
        row[13] = 0.5 * p_mass[p] * v2
        row[14] = p_mass[p] * max(w, 0.0)
    else:
        row[BAD] = 1.0


@njit(cache=True)
def end_row(p_x, p_x0, p_v, p_rho, p_stress, p_mass, gravity, start, end, row):
    """Particles start..end-1 reduced into ``row`` (END_ROW, at END_START), as the device kernel does."""
    one = np.empty(END_ROW)
    for p in range(start, end):
        for q in range(END_ROW):
            one[q] = -math.inf if (q < 6 or SPEED <= q <= RHO_MAX) else 0.0
        particle_row(p, p_x, p_x0, p_v, p_rho, p_stress, p_mass, gravity, one)
        for q in range(END_ROW):
            row[q] = max(row[q], one[q]) if (q < 6 or SPEED <= q <= RHO_MAX) else row[q] + one[q]


def end_rows(state, gravity) -> np.ndarray:
    """The step-end rows of every material block of a host ParticleState, flat (blocks * END_ROW)."""
    rows = np.tile(np.asarray(END_START), len(state.blocks))
    g = np.ascontiguousarray(gravity, dtype=np.float64)
    for k, (s, e) in enumerate(state.blocks):
        end_row(state.p_x, state.p_x0, state.p_v, state.p_rho, state.p_stress, state.p_mass, g, s, e,
                rows[k * END_ROW:(k + 1) * END_ROW])
    return rows
