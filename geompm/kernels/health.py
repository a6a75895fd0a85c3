"""The particles' health in one pass (engine/health.py): the count of non-finite fields, the kinetic energy and
the energy gravity released; and the mask of particles outside a box (engine/health.check_domain).  A device
backend reduces the same sums on the device (backend/cuda_kernels.step_end)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange


@njit(parallel=True, cache=True)
def health_sums(p_x, p_x0, p_v, p_stress, p_mass, gravity):
    """(number of particles with a non-finite field, kinetic energy, energy released by gravity).

    The gravity term sums m g.(x - x0) over the particles that moved down only: the
    energy gravity has released.  A net sum would let one runaway particle thrown
    upwards cancel the descent of the whole mass (a 3D debris blow-up reported its
    supply as 0 J that way); the positive part is still an upper bound of what the
    run can turn into kinetic energy."""
    n, d = p_x.shape
    bad = 0
    ek = 0.0
    wg = 0.0
    for p in prange(n):
        ok = True
        v2 = 0.0
        w = 0.0
        for a in range(d):
            if not (math.isfinite(p_x[p, a]) and math.isfinite(p_v[p, a])):
                ok = False
            v2 += p_v[p, a] * p_v[p, a]
            w += gravity[a] * (p_x[p, a] - p_x0[p, a])
        for k in range(6):
            if not math.isfinite(p_stress[p, k]):
                ok = False
        if ok:
            ek += 0.5 * p_mass[p] * v2
            wg += p_mass[p] * max(w, 0.0)
        else:
            bad += 1
    return bad, ek, wg


@njit(parallel=True, cache=True)
def outside_grid(p_x, lo, hi):
    """Mask of particles outside the box [lo, hi]."""
    n, d = p_x.shape
    out = np.zeros(n, np.bool_)
    for p in prange(n):
        for a in range(d):
            if not (lo[a] <= p_x[p, a] <= hi[a]):
                out[p] = True
    return out
