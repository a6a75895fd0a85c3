"""The overburden of each particle in its column: the loop of assemble.geostatic_stress.

Input: the particles sorted by column, then from the top level down (``level`` is
the height's key, equal for particles at one height; ascending means downward),
their heights [m], densities [kg/m3] and spacings [m].  In each column the
overburden per unit area w [kg/m2] is the density integrated over height from the
top level (which stands for half a particle spacing of material above it) down to
each level, by the trapezoid rule between the levels' mean heights and densities.
One pass over the sorted particles and one over the levels, summing in the same
order as the per-column numpy version it replaces (sums per level in particle
order, running sums down each column).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def column_overburden(col, level, height, rho, spacing):
    n = col.shape[0]
    w = np.empty(n)
    if n == 0:
        return w
    # levels: runs of equal (column, level)
    first = np.empty(n + 1, np.int64)
    nlev = 0
    for k in range(n):
        if k == 0 or col[k] != col[k - 1] or level[k] != level[k - 1]:
            first[nlev] = k
            nlev += 1
    first[nlev] = n
    z = np.zeros(nlev)
    r = np.zeros(nlev)
    for lv in range(nlev):
        for k in range(first[lv], first[lv + 1]):
            z[lv] += height[k]
            r[lv] += rho[k]
        cnt = first[lv + 1] - first[lv]
        z[lv] /= cnt
        r[lv] /= cnt
    top = 0.0
    acc = 0.0
    for lv in range(nlev):
        k0, k1 = first[lv], first[lv + 1]
        if lv == 0 or col[k0] != col[first[lv - 1]]:  # the column's top level
            s = 0.0
            for k in range(k0, k1):
                s += spacing[k]
            top = 0.5 * r[lv] * (s / (k1 - k0))
            acc = 0.0
        else:
            acc += 0.5 * (r[lv] + r[lv - 1]) * (z[lv - 1] - z[lv])
        for k in range(k0, k1):
            w[k] = top + acc
    return w
